"""The compile options of the renderers' hot kernels, in one place."""

from __future__ import annotations

from numba import njit

# numpy's error model: a float division by zero gives inf or nan instead of raising
# ZeroDivisionError. The kernels guard their divisions themselves, and a raise path
# defeats numba's reference-count pruning: every array argument then costs two atomic
# operations per call (measured: a third of the renderer's time went to them).
KERNEL_OPTIONS = {"cache": True, "error_model": "numpy"}


def kernel(func=None, **options):
    """``numba.njit`` with :data:`KERNEL_OPTIONS` (plus ``options``, e.g. ``inline``,
    ``nogil``); usable bare (``@kernel``) or called (``@kernel(inline="always")``)."""
    if func is None:
        return lambda f: njit(**KERNEL_OPTIONS, **options)(f)
    return njit(**KERNEL_OPTIONS, **options)(func)
