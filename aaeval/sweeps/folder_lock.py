"""One writer per sweep folder: the lock ``DIR/sweep.lock``.

A sweep (or a report rebuilding the tables) holds an advisory ``flock`` on ``sweep.lock``
and writes its PID, host, command and start time into it. The kernel drops the ``flock``
when its process ends, however it ends, so a lock file that names a PID but is not locked
is stale and is taken over. The lock file is opened without following links and must be a
regular file.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import os
import socket
import stat
import time
from pathlib import Path
from typing import Callable, Iterator

from aaeval.sweeps.folder_files import CLOEXEC, NOFOLLOW, StoreError, read_own_file

__all__ = ["FolderLock", "FolderInUse"]


class FolderInUse(StoreError):
    """Another process (a sweep, or a report rebuilding the tables) holds the folder's lock."""


class FolderLock:
    """The lock of the sweep folder ``root``; ``log`` names a stale lock taken over."""

    def __init__(self, root: Path, log: Callable[[str], None]):
        self.root = root
        self.path = root / "sweep.lock"
        self.log = log
        self._locked = False

    @contextlib.contextmanager
    def try_lock(self, command: str = "report") -> Iterator[bool]:
        """Hold the lock if no one else does: yields True holding it, False (holding
        nothing) while another process holds it."""
        stack = contextlib.ExitStack()
        try:
            stack.enter_context(self.lock(command))
            held = True
        except FolderInUse:
            held = False
        with stack:
            yield held

    def owner(self) -> dict:
        """Who holds the lock, as it wrote itself into ``sweep.lock`` ({} if unknown)."""
        try:
            return json.loads(read_own_file(self.path, 4096).decode() or "{}")
        except (OSError, ValueError):
            return {}

    @contextlib.contextmanager
    def lock(self, command: str = "sweep") -> Iterator[None]:
        """Hold ``sweep.lock`` (an advisory ``flock`` plus the owner's PID) while writing.

        The kernel drops the ``flock`` when its process ends, however it ends, so a lock
        file that names a PID but is not locked is stale and is taken over.
        """
        if self._locked:  # this store already holds it (the sweep rebuilding its tables)
            yield
            return
        self.root.mkdir(parents=True, exist_ok=True)
        try:  # never through a link: O_RDWR|O_CREAT on a link would open, then truncate, its target
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT | NOFOLLOW | CLOEXEC
                         | getattr(os, "O_NONBLOCK", 0), 0o666)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise StoreError(f"{self.path} is a symbolic link; a sweep opens only its own files "
                                 f"inside {self.root} (remove the link)") from None
            raise
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise StoreError(f"{self.path} is not a regular file; a sweep needs it as its lock "
                                 "(move it away)")
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                owner = _lock_owner(fd)
                raise FolderInUse(
                    f"{self.root} is in use by another {owner.get('command', 'sweep')} (pid {owner.get('pid', '?')} on "
                    f"{owner.get('host', '?')}, started {owner.get('started', '?')}); wait for it or stop it"
                ) from None
            stale = _lock_owner(fd)
            if stale.get("pid"):
                self.log(f"stale lock {self.path} of pid {stale['pid']} on {stale.get('host', '?')} "
                         "(that sweep no longer runs) taken over")
            owner = {"pid": os.getpid(), "host": socket.gethostname(), "command": command,
                     "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
            os.ftruncate(fd, 0)
            os.pwrite(fd, (json.dumps(owner) + "\n").encode(), 0)
            self._locked = True
            try:
                yield
            finally:
                self._locked = False
                os.ftruncate(fd, 0)  # kept, not unlinked: unlinking a locked file races
        finally:
            os.close(fd)  # releases the flock


def _lock_owner(fd: int) -> dict:
    try:
        owner = json.loads(os.pread(fd, 4096, 0).decode() or "{}")
    except (OSError, ValueError):
        return {}
    return owner if isinstance(owner, dict) else {}
