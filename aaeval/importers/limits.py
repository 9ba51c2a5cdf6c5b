"""Stated limits of ``aaeval import``, checked before or while the work is done.

An import that would pass one is refused with one line naming the limit (an
:class:`ImportLimitError`, a ``ValueError``: exit code 2 on the command line):

- :data:`MAX_ELEMENTS` drawable SVG elements after ``<use>`` expansion, counted on the
  parsed XML before anything is expanded (a ``<use>`` bomb never runs);
- :data:`MAX_VERTICES` flattened vertices (curves and stroke outlines) in one import;
- :data:`MAX_GLYPHS` glyphs of text (characters times sizes);
- a flattening tolerance of at least :data:`TOLERANCE_RTOL` times the image's larger side
  (finer than that is below float64's resolution of the coordinates and only costs
  vertices); :func:`min_tolerance` gives the bound.

Fill rules (:mod:`aaeval.importers.fill`) have their own limits, raised as a
:class:`FillError`: :data:`MAX_EDGES` edges in one outline (as given, or once its crossings
would be cut: checked before the cut) and :data:`MAX_PAIRS` edge pairs whose boxes overlap
(a quadratic number of crossings), refused instead of running for hours.

The file itself is read by :func:`aaeval.readlimits.read_bytes` (regular files only, of
bounded size).
"""

from __future__ import annotations

import contextvars
import math

__all__ = ["ImportLimitError", "MAX_ELEMENTS", "MAX_VERTICES", "MAX_GLYPHS", "TOLERANCE_RTOL",
           "min_tolerance", "check_tolerance", "VertexBudget", "charge", "FillError", "MAX_EDGES", "MAX_PAIRS"]

MAX_ELEMENTS = 20_000
MAX_VERTICES = 2_000_000
MAX_GLYPHS = 20_000
TOLERANCE_RTOL = 1e-7
MAX_EDGES = 300_000
MAX_PAIRS = 40_000_000


class ImportLimitError(ValueError):
    """An import over one of the stated limits."""


class FillError(ValueError):
    """An outline too large or too complex to resolve within the stated limits."""


def min_tolerance(width: float, height: float) -> float:
    """The smallest flattening tolerance taken for an image of this size (pixels)."""
    return TOLERANCE_RTOL * max(1.0, float(width), float(height))


def check_tolerance(tol: float, width: float, height: float, what: str = "--tolerance") -> None:
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ImportLimitError(f"{what} must be a positive number of pixels, got {tol!r}")
    low = min_tolerance(width, height)
    if tol < low:
        raise ImportLimitError(f"{what} {tol:g} is below the limit of {low:.3g} px for a "
                               f"{width:g}x{height:g} image ({TOLERANCE_RTOL:g} of its larger side)")


class VertexBudget:
    """Counts vertices as they are made; raises once more than ``limit`` are asked for."""

    def __init__(self, limit: int = MAX_VERTICES):
        self.limit = int(limit)
        self.used = 0

    def __call__(self, n: int) -> None:
        self.used += int(n)
        if self.used > self.limit:
            raise ImportLimitError(f"the import needs more than {self.limit} vertices (the limit); "
                                   "raise --tolerance or import less")


_current: contextvars.ContextVar[VertexBudget | None] = contextvars.ContextVar("aaeval_vertex_budget", default=None)


def charge(n: int) -> None:
    """Count ``n`` vertices against the budget of the import in progress (if any)."""
    budget = _current.get()
    if budget is not None:
        budget(n)


class budget_scope:
    """``with budget_scope(VertexBudget()) as b:`` makes ``b`` the budget :func:`charge` uses."""

    def __init__(self, budget: VertexBudget):
        self.budget = budget

    def __enter__(self) -> VertexBudget:
        self._token = _current.set(self.budget)
        return self.budget

    def __exit__(self, *exc) -> None:
        _current.reset(self._token)
