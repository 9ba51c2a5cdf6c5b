"""Keep numba's on-disk kernel cache consistent with the kernels' source.

numba's ``cache=True`` checks only the source file of the function it compiles: a kernel
that calls into another module's kernel keeps its stale machine code when only that other
module changes. Keying the cache folder by a hash of every module that defines kernels
makes any kernel edit start a fresh cache.

A damaged cache file (a truncated write, a full disk) makes numba fail every call of that
kernel with an UnpicklingError; :func:`configure` checks the cache's pickles first (their
structure only, without loading them) and clears a damaged cache with a one-line warning,
so the kernels compile afresh.
"""

from __future__ import annotations

import hashlib
import os
import pickletools
import shutil
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def kernel_source_hash() -> str:
    digest = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_bytes()
        # a kernel module names numba's njit or the project's kernel decorator (_jit.kernel)
        if b"njit" in text or b"aaeval._jit import" in text:
            digest.update(path.relative_to(PACKAGE).as_posix().encode())
            digest.update(text)
    return digest.hexdigest()[:16]


def pickle_problem(path: Path) -> str | None:
    """Why ``path`` is not a whole sequence of pickles (numba's .nbi holds two, .nbc one)."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        return exc.strerror or str(exc)
    if not data:
        return "empty"
    position = 0
    try:
        while position < len(data):
            for opcode, _, at in pickletools.genops(data[position:]):
                if opcode.name == "STOP":
                    position += at + 1
                    break
            else:
                return "truncated"
    except (ValueError, EOFError) as exc:
        return f"truncated or corrupt ({exc})"
    return None


def check_cache(folder: Path) -> None:
    """Clear ``folder`` (a numba cache) if any of its files is damaged, with a warning."""
    if not folder.is_dir():
        return
    for path in sorted(folder.rglob("*.nb[ic]")):
        if path.name.startswith("."):
            continue
        problem = pickle_problem(path)
        if problem is not None:
            shutil.rmtree(folder, ignore_errors=True)  # a cache: everything in it is rebuilt
            print(f"aaeval: warning: numba cache {folder} was damaged ({path.name}: {problem}); "
                  "cleared, the kernels compile again", file=sys.stderr)
            return


def configure() -> None:
    """Point numba at a cache folder for this kernel source, unless the user chose one,
    and clear it if it is damaged."""
    if "NUMBA_CACHE_DIR" not in os.environ:
        base = Path(os.environ.get("AAEVAL_CACHE_DIR", Path.home() / ".cache" / "aaeval"))
        os.environ["NUMBA_CACHE_DIR"] = str(base / "numba" / kernel_source_hash())
    check_cache(Path(os.environ["NUMBA_CACHE_DIR"]))
