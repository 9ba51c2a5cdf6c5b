"""Choosing Mitsuba's variant at run time, and finding a libLLVM that Dr.Jit can use.

Mitsuba's variant is global to the process, and Dr.Jit reads ``DRJIT_LIBLLVM_PATH`` once,
when its LLVM backend first starts. :func:`import_mitsuba` is therefore the one way aaeval
imports Mitsuba: it points Dr.Jit at a usable libLLVM before anything can start the LLVM
backend, then sets the variant asked for.

Order of preference for ``variant="auto"`` (:func:`select_variant`):

1. ``cuda_ad_rgb`` / ``cuda_rgb`` when Dr.Jit's CUDA backend starts (a GPU and a driver);
2. ``llvm_ad_rgb`` / ``llvm_rgb`` with libLLVM >= 16 (LLVM 14 is rejected by Dr.Jit and
   LLVM 15 aborts on the first render, as seen on this project's machines);
3. ``scalar_rgb``, with a one-line warning (correct, but one ray at a time).

Only RGB variants are accepted: the scene's colours are linear RGB and a spectral
variant would round-trip them through spectra.
"""

from __future__ import annotations

import functools
import glob
import os
import re
import warnings
from pathlib import Path
from typing import Iterable, Mapping

__all__ = [
    "LLVM_MIN_VERSION",
    "LIBLLVM_ENV",
    "LIBRARY_DIRS",
    "libllvm_version",
    "find_libllvm",
    "configure_libllvm",
    "import_mitsuba",
    "select_variant",
    "VariantError",
]

LLVM_MIN_VERSION = 16
LIBLLVM_ENV = "DRJIT_LIBLLVM_PATH"

# Where distributions put libLLVM; globs are expanded in order.
LIBRARY_DIRS = (
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib64",
    "/usr/lib",
    "/usr/local/lib",
    "/usr/lib/llvm-*/lib",
    "/usr/lib64/llvm*/lib",
    "/opt/homebrew/opt/llvm/lib",
    "/opt/homebrew/opt/llvm@*/lib",
    "/usr/local/opt/llvm/lib",
    "/usr/local/opt/llvm@*/lib",
)

_LIB_NAME = re.compile(r"^libLLVM(?:[-.].*)?\.(?:so(?:\..*)?|dylib)$")
# the major version, from the file name first (libLLVM-19.so, libLLVM.so.19.1,
# libLLVM-14.0.6.so.1, libLLVM.19.dylib), else from a folder (llvm-19, llvm@17, Cellar/llvm/19.1.0)
_VERSION_IN_NAME = (re.compile(r"^libLLVM-(\d+)"), re.compile(r"^libLLVM\.so\.(\d+)"), re.compile(r"^libLLVM\.(\d+)\.dylib$"))
_VERSION_IN_DIR = (re.compile(r"^llvm-(\d+)$"), re.compile(r"^llvm@(\d+)$"))

JIT_RGB_VARIANTS = ("cuda_ad_rgb", "cuda_rgb", "llvm_ad_rgb", "llvm_rgb")


class VariantError(ValueError):
    """A Mitsuba variant that was asked for cannot be used here (a bad option value)."""


def libllvm_version(path: str | Path) -> int | None:
    """Major LLVM version of a libLLVM file, read from its name or its folders.

    Symbolic links are followed too (Homebrew's ``opt/llvm`` points into
    ``Cellar/llvm/19.1.0``). Returns None when no version can be read.
    """
    for candidate in dict.fromkeys((Path(path), Path(os.path.realpath(path)))):
        for pattern in _VERSION_IN_NAME:
            if m := pattern.match(candidate.name):
                return int(m.group(1))
        parts = candidate.parts
        for i, part in enumerate(parts):
            for pattern in _VERSION_IN_DIR:
                if m := pattern.match(part):
                    return int(m.group(1))
            if part == "llvm" and i > 0 and parts[i - 1] == "Cellar" and i + 1 < len(parts):
                if m := re.match(r"^(\d+)", parts[i + 1]):
                    return int(m.group(1))
    return None


def find_libllvm(
    search_dirs: Iterable[str] = LIBRARY_DIRS,
    env: Mapping[str, str] | None = None,
    minimum: int = LLVM_MIN_VERSION,
) -> Path | None:
    """The libLLVM Dr.Jit should load: ``$DRJIT_LIBLLVM_PATH`` if set, else the newest >= ``minimum``.

    Libraries whose version cannot be read, or is below ``minimum``, are skipped. Returns
    None when nothing usable is found.
    """
    env = os.environ if env is None else env
    if env.get(LIBLLVM_ENV):
        return Path(env[LIBLLVM_ENV])
    best: tuple[int, str] | None = None
    for pattern in search_dirs:
        for folder in sorted(glob.glob(pattern)):
            try:
                names = sorted(os.listdir(folder))
            except OSError:
                continue
            for name in names:
                path = os.path.join(folder, name)
                if not _LIB_NAME.match(name) or not os.path.isfile(path):
                    continue
                version = libllvm_version(path)
                if version is None or version < minimum:
                    continue
                if best is None or version > best[0]:
                    best = (version, path)
    return None if best is None else Path(best[1])


def configure_libllvm() -> Path | None:
    """Set ``$DRJIT_LIBLLVM_PATH`` to :func:`find_libllvm`'s choice unless already set."""
    path = find_libllvm()
    if path is not None and not os.environ.get(LIBLLVM_ENV):
        os.environ[LIBLLVM_ENV] = str(path)
    return path


def import_mitsuba(variant: str | None = "auto"):
    """Import Mitsuba with libLLVM configured, and set a variant.

    Parameters
    ----------
    variant : str or None
        ``"auto"``: :func:`select_variant`'s choice. A variant name: that variant (it must
        be an RGB variant this build of Mitsuba has and this machine can run). None: keep
        the variant already set, or set ``scalar_rgb`` if none is (enough for ``Bitmap``).

    Returns
    -------
    module
        The ``mitsuba`` module, with the variant set.
    """
    configure_libllvm()
    import mitsuba as mi

    if variant is None:
        if mi.variant() is None:
            mi.set_variant("scalar_rgb")
        return mi
    wanted = select_variant() if variant == "auto" else _checked_variant(variant)
    if mi.variant() != wanted:
        mi.set_variant(wanted)
    return mi


@functools.cache
def select_variant() -> str:
    """The fastest RGB variant that works on this machine (probed once per process)."""
    import mitsuba as mi

    available = set(mi.variants())
    for name in JIT_RGB_VARIANTS:
        if name in available and _backend_works(name):
            return name
    llvm = f"{LIBLLVM_ENV}={os.environ[LIBLLVM_ENV]} is not a usable libLLVM >= {LLVM_MIN_VERSION}" if os.environ.get(
        LIBLLVM_ENV
    ) else f"no libLLVM >= {LLVM_MIN_VERSION} found (set {LIBLLVM_ENV})"
    warnings.warn(
        f"aaeval: no CUDA GPU and {llvm}; Mitsuba falls back to the slow scalar_rgb variant",
        RuntimeWarning,
        stacklevel=2,
    )
    return "scalar_rgb"


def _checked_variant(name: str) -> str:
    import mitsuba as mi

    if name not in mi.variants():
        raise VariantError(f"Mitsuba variant {name!r} is not built here; available: {', '.join(mi.variants())}")
    if not name.endswith("_rgb"):
        raise VariantError(f"Mitsuba variant {name!r} is not an RGB variant; scene colours are linear RGB")
    if name != "scalar_rgb" and not _backend_works(name):
        raise VariantError(f"Mitsuba variant {name!r} cannot run on this machine (no {_backend_name(name)} backend)")
    return name


def _backend_name(variant: str) -> str:
    return "CUDA" if variant.startswith("cuda") else "LLVM (libLLVM >= 16)"


@functools.cache
def _backend_works(variant: str) -> bool:
    """Whether Dr.Jit's backend for ``variant`` starts; never raises."""
    configure_libllvm()
    try:
        import drjit as dr

        if variant.startswith("cuda"):
            return bool(dr.has_backend(dr.JitBackend.CUDA))
        if not os.environ.get(LIBLLVM_ENV):
            # without a path Dr.Jit would try the system's default libLLVM, which may be 15
            return False
        if not dr.has_backend(dr.JitBackend.LLVM):
            return False
        return dr.detail.llvm_version()[0] >= LLVM_MIN_VERSION
    except Exception:  # a broken driver or library must only mean "not this variant"
        return False
