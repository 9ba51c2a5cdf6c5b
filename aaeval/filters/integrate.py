"""Exact integration of visible pieces against a separable filter (native stages, Python glue).

The image plane is cut into *knot cells* ``[m - 1/2, m + 1/2] x [n - 1/2, n + 1/2]``
(integer ``m, n``; ``0 <= m <= W``, ``0 <= n <= H``; the border cells are half cells,
since samples lie only inside the image). Over one cell the filter of every pixel it
reaches is one polynomial piece (or one smooth Gaussian), so a pixel's value is a sum over
cells of integrals of basis functions over the visible pieces in the cell:

- polynomial filters: the piece's moments ``M[a, b] = ∫∫ u^a v^b dA`` (``u = x - m``,
  ``v = y - n``, ``a, b <= degree``); a pixel's weight from the cell is
  ``sum_ab E[p, a] E[q, b] M[a, b]`` with ``E`` the filter's cell-local coefficients;
- the Gaussian: directly ``G[p, q] = ∫∫ k(u + p + 1/2) k(v + q + 1/2) dA`` for the 2R x 2R
  pixels the cell reaches.

Both are integrals of ``phi_a(u) psi_b(v)``, computed by Green's theorem as
``∮ Phi_a(u) psi_b(v) dv`` with ``Phi_a' = phi_a`` along the piece's straight edges.
For polynomials the edge integrand has degree ``2 degree + 1 <= 7`` and 4-point
Gauss-Legendre is exact. For the Gaussian (``Phi`` is an erf) the edges are integrated
with :data:`GAUSS_NODES`-point Gauss-Legendre; an edge inside one unit cell is at most
sqrt(2) long, and the rule's error there is below 1e-14 (measured in
``tests/filters/test_filters.py::test_gaussian_edge_quadrature_converged``).

Stages, each tested on tiny hand-made polygons:
:func:`piece_integrals` (one polygon inside a cell), :func:`accumulate_rings` (rings of
any size cut on the knot grid, integrals accumulated per cell and channel),
:func:`combine_cells` (cells into pixels; :func:`combine_cells_numpy` is the same in numpy).
"""

from __future__ import annotations

import numpy as np

from aaeval.native import catmull as _catmull
from aaeval.filters.registry import KIND_GAUSSIAN, KIND_POLYNOMIAL, PixelFilter

__all__ = [
    "GAUSS_NODES",
    "filter_kernel_args",
    "basis_count",
    "piece_integrals",
    "accumulate_rings",
    "combine_cells",
    "combine_cells_numpy",
    "cell_basis_matrix",
]

# Gaussian edges (erf times Gaussian along a segment of length <= sqrt(2)) are integrated
# with this many Gauss-Legendre nodes; polynomial edges with 4 (exact for degree 7). The
# nodes live with the native stages (src/catmull/moments.hpp).
GAUSS_NODES = 12


def basis_count(filt: PixelFilter) -> int:
    """Number of basis functions per axis: ``degree + 1`` (polynomial) or ``2R`` (Gaussian)."""
    if filt.kind == KIND_GAUSSIAN:
        return 2 * filt.knot_radius
    return filt.pieces.shape[1]


def filter_kernel_args(filt: PixelFilter) -> tuple:
    """``(kind, R, K, alpha, bias)``: what the native stages need to know about a filter."""
    if filt.kind not in (KIND_POLYNOMIAL, KIND_GAUSSIAN):
        raise ValueError(f"filter {filt.name!r} is not integrated on knot cells (box has its own exact path)")
    alpha, bias = filt.gaussian_alpha_bias if filt.kind == KIND_GAUSSIAN else (0.0, 0.0)
    return filt.kind, filt.knot_radius, basis_count(filt), alpha, bias


def piece_integrals(xs, ys, start, n, ox, oy, kind, radius, k, alpha, bias, out):
    """Integrals of ``phi_a(u) psi_b(v)`` over one polygon, written to ``out[a, b]`` (k x k).

    The polygon is ``xs/ys[start:start+n]`` (positive shoelace area; negative gives the
    negated integrals, which is how holes subtract), lying inside the cell centred at
    ``(ox, oy)``; ``u = x - ox``, ``v = y - oy``. ``kind`` polynomial: ``phi_a = u^a``,
    ``psi_b = v^b``; Gaussian: ``phi_a(u) = k(u + a - radius + 1/2)`` and the same in v.
    Native (``src/catmull/moments.hpp``): Green's theorem, Gauss-Legendre along each edge.
    """
    _catmull.piece_integrals(xs, ys, int(start), int(n), float(ox), float(oy), int(kind), int(radius), int(k),
                             float(alpha), float(bias), out)


def column_part_integrals(xs, ys, start, n, col, ox, oy, kind, radius, k, alpha, bias, out) -> bool:
    """Integrals of ``phi_a(u) psi_b(v)`` over the polygon's part in pixel column
    ``[col, col + 1]``, written to ``out[a, b]`` without cutting the part out: by Green's
    theorem in the form along ``du``, to which the column's sides add nothing (the route a
    render's front pieces take, ``src/catmull/moments.hpp``). ``False`` (``out`` untouched)
    for a filter without that form (only the tent and the cubics have it)."""
    return bool(_catmull.column_part_integrals(xs, ys, int(start), int(n), int(col), float(ox), float(oy), int(kind),
                                               int(radius), int(k), float(alpha), float(bias), out))


def accumulate_rings(xs, ys, starts, lengths, weights, width, height, kind, radius, k, alpha, bias, acc):
    """Cut every ring on the knot grid (inside the image) and accumulate its integrals per cell.

    ``acc[n, m, a, b, c] += weights[r, c] * integrals[a, b]`` of ring ``r``'s part in cell
    ``(m, n)`` (shape ``(H + 1, W + 1, k, k, channels)``). Rings are signed (holes have
    negative shoelace area and subtract). Native (``src/catmull/moments.hpp``).
    """
    _catmull.accumulate_rings(np.ascontiguousarray(xs, dtype=np.float64), np.ascontiguousarray(ys, dtype=np.float64),
                              np.ascontiguousarray(starts, dtype=np.int64), np.ascontiguousarray(lengths, dtype=np.int64),
                              np.ascontiguousarray(weights, dtype=np.float64), int(width), int(height), int(kind),
                              int(radius), int(k), float(alpha), float(bias), acc)


def cell_basis_matrix(filt: PixelFilter) -> np.ndarray:
    """``E[p + R, a]``: pixel weight of basis function ``a`` for the piece ``p`` of the filter.

    Polynomial: the cell-local coefficients; Gaussian: the identity (its basis functions
    are the shifted profiles themselves).
    """
    if filt.kind == KIND_GAUSSIAN:
        return np.eye(2 * filt.knot_radius)
    return np.asarray(filt.pieces, dtype=np.float64)


def combine_cells(acc: np.ndarray, filt: PixelFilter, width: int, height: int, threads: int = 1) -> np.ndarray:
    """Pixel sums ``(H, W, channels)`` from cell accumulators ``(H+1, W+1, k, k, channels)``.

    Pixel ``i`` takes piece ``p = m - i - 1`` of the filter from cell ``m``
    (``p = -R .. R-1``); separable, so x is contracted first, then y:
    ``t[n, i, b] = sum_p sum_a acc[n, i + 1 + p, a, b] E[p + R, a]``, then
    ``out[j, i] = sum_q sum_b t[j + 1 + q, i, b] E[q + R, b]``. Native
    (``src/catmull/moments.hpp``, bands of rows on ``threads`` threads, the same bits for any
    count); :func:`combine_cells_numpy` is the same sums in numpy, with the same bits.
    """
    e = np.ascontiguousarray(cell_basis_matrix(filt), dtype=np.float64)
    return _catmull.combine_cells(np.ascontiguousarray(acc, dtype=np.float64), e, int(filt.knot_radius), int(width),
                                  int(height), int(threads))


def combine_cells_numpy(acc: np.ndarray, filt: PixelFilter, width: int, height: int) -> np.ndarray:
    """:func:`combine_cells` in numpy (the reference the tests compare the native one with)."""
    e = cell_basis_matrix(filt)
    r = filt.knot_radius
    padded = np.pad(acc, ((r, r), (r, r), (0, 0), (0, 0), (0, 0)))
    # cell m sits at padded index m + r; pixel i needs cells i + 1 + p for p in [-r, r)
    tx = np.zeros((padded.shape[0], width) + acc.shape[3:])
    for p in range(-r, r):
        cells = padded[:, r + 1 + p: r + 1 + p + width]
        tx += np.einsum("nmab...,a->nmb...", cells, e[p + r])
    out = np.zeros((height, width) + acc.shape[4:])
    for q in range(-r, r):
        cells = tx[r + 1 + q: r + 1 + q + height]
        out += np.einsum("nmb...,b->nm...", cells, e[q + r])
    return out
