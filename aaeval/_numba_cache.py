"""Keep numba's on-disk kernel cache consistent with the kernels' source.

numba's ``cache=True`` checks only the source file of the function it compiles: a kernel
that calls into another module's kernel keeps its stale machine code when only that other
module changes. Keying the cache folder by a hash of every module that defines kernels
makes any kernel edit start a fresh cache.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent


def kernel_source_hash() -> str:
    digest = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_bytes()
        if b"njit" in text:
            digest.update(path.relative_to(PACKAGE).as_posix().encode())
            digest.update(text)
    return digest.hexdigest()[:16]


def configure() -> None:
    """Point numba at a cache folder for this kernel source, unless the user chose one."""
    if "NUMBA_CACHE_DIR" in os.environ:
        return
    base = Path(os.environ.get("AAEVAL_CACHE_DIR", Path.home() / ".cache" / "aaeval"))
    os.environ["NUMBA_CACHE_DIR"] = str(base / "numba" / kernel_source_hash())
