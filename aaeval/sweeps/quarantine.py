"""Damaged files of a sweep folder set aside, never deleted.

A cell record, image or reference that fails its check is named (one line through the
store's ``log``) and moved, with the other files of its cell, to
``DIR/quarantine/<time>/`` under the same relative path, so the next sweep runs the cell
again and the user can still look at what was there. A link is moved as a link; its target
is never touched.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Callable

from aaeval.sweeps.folder_files import real_folder

__all__ = ["Quarantine", "stamp"]


def stamp() -> str:
    """A folder name for this moment and this process: ``20261204T231500Z-4242``."""
    return time.strftime("%Y%m%dT%H%M%SZ", time.gmtime()) + f"-{os.getpid()}"


class Quarantine:
    """The quarantine folder of the sweep folder ``root``, made on its first use."""

    def __init__(self, root: Path, log: Callable[[str], None]):
        self.root = root
        self.log = log
        self._folder: Path | None = None

    def set_aside(self, cell: Path, problem: str, heal: bool, companions: list[Path]) -> None:
        """Name the damaged file ``cell`` and ``problem``; with ``heal``, move it and its
        ``companions`` (the cell's image and map) here, so that the cell runs again."""
        if not heal:
            self.log(f"damaged sweep file {cell}: {problem} (left in place; the cell counts as not done)")
            return
        moved = self.move(cell, heal)
        for path in companions:
            if os.path.lexists(path):  # a link is moved itself; its target is never touched
                self.move(path, heal)
        self.log(f"damaged sweep file {cell}: {problem}; moved to {moved.parent}, the cell will run again")

    def move(self, path: Path, heal: bool) -> Path:
        """Move ``path`` (a file of the sweep folder) here when ``heal``; where it is now."""
        if not heal:
            return path
        if self._folder is None:
            self._folder = self.root / "quarantine" / stamp()
        target = self._folder / path.relative_to(self.root)
        real_folder(self.root, target.parent)  # quarantine/ must be a real folder of this one, not a link
        os.replace(path, target)  # never deleted: the user may want to look at it (a link moves as a link)
        return target
