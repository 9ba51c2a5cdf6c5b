"""Per-pixel maps computed once per image pair and read by every metric that needs them.

A sweep cell computes several metrics of one (reference, image) pair, and some of them read
the same per-pixel map: ``ciede2000_mean`` and ``ciede2000_p95`` the CIEDE2000 map, the
``flip`` metric and the viewer's FLIP map one FLIP evaluation. Inside :func:`maps_once_per_pair`
a function decorated with :func:`once_per_pair` is evaluated once per pair of arrays (the same
objects, not changed in between) and its answer is given again to every later call. What
was seen belongs to the thread (the context) that entered the block: a Dask worker runs
several cells at once on threads of one process.
"""

from __future__ import annotations

import functools
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Callable

__all__ = ["maps_once_per_pair", "once_per_pair"]

# Inside maps_once_per_pair(): (function, image_true, image_test, options, answer) seen there,
# in this thread's context (None outside the block)
_SEEN: ContextVar[list | None] = ContextVar("aaeval_maps_seen", default=None)


@contextmanager
def maps_once_per_pair():
    """Within this block every :func:`once_per_pair` function is evaluated once per pair of
    arrays; the arrays are held (not copied) until the block ends, so their identities stay
    theirs."""
    token = _SEEN.set([])
    try:
        yield
    finally:
        _SEEN.reset(token)


def once_per_pair(compute: Callable) -> Callable:
    """``compute(image_true, image_test, *options)`` answered again, inside
    :func:`maps_once_per_pair`, for a pair of arrays (by identity) and options (by equality)
    it has seen there; outside, computed each time."""

    @functools.wraps(compute)
    def shared(image_true, image_test, *options):
        seen = _SEEN.get()
        if seen is None:
            return compute(image_true, image_test, *options)
        for function, a, b, seen_options, answer in seen:
            if function is compute and a is image_true and b is image_test and seen_options == options:
                return answer
        answer = compute(image_true, image_test, *options)
        seen.append((compute, image_true, image_test, options, answer))
        return answer

    def remember(image_true, image_test, answer, *options) -> None:
        """Inside :func:`maps_once_per_pair`: ``answer`` is what the pair gives (computed in
        bulk with others); outside, nothing."""
        seen = _SEEN.get()
        if seen is not None:
            seen.append((compute, image_true, image_test, options, answer))

    shared.remember = remember
    return shared
