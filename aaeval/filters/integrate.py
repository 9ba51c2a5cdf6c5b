"""Exact integration of visible pieces against a separable filter (numba stages).

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
``tests/test_filters.py::test_gaussian_edge_quadrature_converged``).

Stages, each tested on tiny hand-made polygons:
:func:`piece_integrals` (one polygon inside a cell), :func:`accumulate_rings` (rings of
any size cut on the knot grid, integrals accumulated per cell and channel),
:func:`combine_cells` (cells into pixels, numpy).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from aaeval.filters.registry import KIND_GAUSSIAN, KIND_POLYNOMIAL, PixelFilter
from aaeval.renderers._clip import clip_side

__all__ = [
    "GAUSS_NODES",
    "filter_kernel_args",
    "basis_count",
    "piece_integrals",
    "accumulate_rings",
    "combine_cells",
    "cell_basis_matrix",
]

# exact for the degree-7 edge polynomials of cubic filters
_POLY_T, _POLY_W = np.polynomial.legendre.leggauss(4)
# Gaussian edges (erf times Gaussian along a segment of length <= sqrt(2))
GAUSS_NODES = 12
_GAUSS_T, _GAUSS_W = np.polynomial.legendre.leggauss(GAUSS_NODES)
# nodes on [0, 1]
_POLY_T = 0.5 * (_POLY_T + 1.0)
_POLY_W = 0.5 * _POLY_W
_GAUSS_T = 0.5 * (_GAUSS_T + 1.0)
_GAUSS_W = 0.5 * _GAUSS_W


def basis_count(filt: PixelFilter) -> int:
    """Number of basis functions per axis: ``degree + 1`` (polynomial) or ``2R`` (Gaussian)."""
    if filt.kind == KIND_GAUSSIAN:
        return 2 * filt.knot_radius
    return filt.pieces.shape[1]


def filter_kernel_args(filt: PixelFilter) -> tuple:
    """``(kind, R, K, alpha, bias)``: what the numba stages need to know about a filter."""
    if filt.kind not in (KIND_POLYNOMIAL, KIND_GAUSSIAN):
        raise ValueError(f"filter {filt.name!r} is not integrated on knot cells (box has its own exact path)")
    alpha, bias = filt.gaussian_alpha_bias if filt.kind == KIND_GAUSSIAN else (0.0, 0.0)
    return filt.kind, filt.knot_radius, basis_count(filt), alpha, bias


@njit(cache=True, inline="always")
def _gauss_primitive(t, alpha, bias):
    """An antiderivative of ``exp(alpha t^2) - bias``."""
    c = math.sqrt(-alpha)
    return (0.8862269254527580 / c) * math.erf(c * t) - bias * t  # sqrt(pi)/2


@njit(cache=True)
def piece_integrals(xs, ys, start, n, ox, oy, kind, radius, k, alpha, bias, out):
    """Integrals of ``phi_a(u) psi_b(v)`` over one polygon, written to ``out[a, b]`` (k x k).

    The polygon is ``xs/ys[start:start+n]`` (positive shoelace area; negative gives the
    negated integrals, which is how holes subtract), lying inside the cell centred at
    ``(ox, oy)``; ``u = x - ox``, ``v = y - oy``. ``kind`` polynomial: ``phi_a = u^a``,
    ``psi_b = v^b``; Gaussian: ``phi_a(u) = k(u + a - radius + 1/2)`` and the same in v.
    """
    for a in range(k):
        for b in range(k):
            out[a, b] = 0.0
    if kind == KIND_POLYNOMIAL:
        nodes = _POLY_T
        weights = _POLY_W
    else:
        nodes = _GAUSS_T
        weights = _GAUSS_W
    phi = np.empty(k)
    psi = np.empty(k)
    for i in range(n):
        j = start + (i + 1) % n
        u0 = xs[start + i] - ox
        v0 = ys[start + i] - oy
        du = xs[j] - ox - u0
        dv = ys[j] - oy - v0
        if dv == 0.0:
            continue  # ∮ Phi dv vanishes along a horizontal edge
        for q in range(nodes.size):
            u = u0 + nodes[q] * du
            v = v0 + nodes[q] * dv
            w = weights[q] * dv
            if kind == KIND_POLYNOMIAL:
                up = u
                vp = 1.0
                for a in range(k):
                    phi[a] = up / (a + 1)
                    psi[a] = vp
                    up *= u
                    vp *= v
            else:
                for a in range(k):
                    c = a - radius + 0.5
                    phi[a] = _gauss_primitive(u + c, alpha, bias)
                    psi[a] = math.exp(alpha * (v + c) * (v + c)) - bias
            for a in range(k):
                wa = w * phi[a]
                for b in range(k):
                    out[a, b] += wa * psi[b]


@njit(cache=True)
def _clip_box(xs, ys, start, n, x0, x1, y0, y1, bx, by, bf):
    """Sutherland-Hodgman clip of one ring to ``[x0, x1] x [y0, y1]``; returns (start, count) in the buffers.

    A concave ring may come back with zero-width bridges along the box's sides; they
    bound no area and cancel in every edge integral.
    """
    # ping-pong between the two halves of the buffers
    half = bx.size // 2
    fl = np.zeros(n, np.uint8)
    m = clip_side(xs[start:start + n], ys[start:start + n], fl, 0, n, 1.0, 0.0, -x0, 1, bx, by, bf, 0)
    if m < 3:
        return 0, 0
    m = clip_side(bx, by, bf, 0, m, 1.0, 0.0, -x1, -1, bx, by, bf, half)
    if m < 3:
        return 0, 0
    m = clip_side(bx, by, bf, half, m, 0.0, 1.0, -y0, 1, bx, by, bf, 0)
    if m < 3:
        return 0, 0
    m = clip_side(bx, by, bf, 0, m, 0.0, 1.0, -y1, -1, bx, by, bf, half)
    if m < 3:
        return 0, 0
    return half, m


@njit(cache=True)
def accumulate_rings(xs, ys, starts, lengths, weights, width, height, kind, radius, k, alpha, bias, acc):
    """Cut every ring on the knot grid (inside the image) and accumulate its integrals per cell.

    ``acc[n, m, a, b, c] += weights[r, c] * integrals[a, b]`` of ring ``r``'s part in cell
    ``(m, n)`` (shape ``(H + 1, W + 1, k, k, channels)``). Rings are signed (holes have
    negative shoelace area and subtract).
    """
    nch = weights.shape[1]
    out = np.empty((k, k))
    for r in range(starts.size):
        s = starts[r]
        n = lengths[r]
        if n < 3:
            continue
        # a line clip adds at most one vertex per edge: 4 clips stay below 16 n
        size = 2 * (16 * n + 16)
        bx = np.empty(size)
        by = np.empty(size)
        bf = np.empty(size, np.uint8)
        cx = np.empty(size)
        cy = np.empty(size)
        cf = np.empty(size, np.uint8)
        xmin = xs[s:s + n].min()
        xmax = xs[s:s + n].max()
        ymin = ys[s:s + n].min()
        ymax = ys[s:s + n].max()
        m0 = max(0, int(math.floor(xmin + 0.5)))
        m1 = min(width, int(math.floor(xmax + 0.5)))
        n0 = max(0, int(math.floor(ymin + 0.5)))
        n1 = min(height, int(math.floor(ymax + 0.5)))
        for row in range(n0, n1 + 1):
            y0 = max(row - 0.5, 0.0)
            y1 = min(row + 0.5, float(height))
            # the band of this cell row, then each cell of it
            bs, bn = _clip_box(xs, ys, s, n, 0.0, float(width), y0, y1, bx, by, bf)
            if bn < 3:
                continue
            c0 = max(m0, int(math.floor(bx[bs:bs + bn].min() + 0.5)))
            c1 = min(m1, int(math.floor(bx[bs:bs + bn].max() + 0.5)))
            for col in range(c0, c1 + 1):
                x0 = max(col - 0.5, 0.0)
                x1 = min(col + 0.5, float(width))
                cs, cn = _clip_box(bx, by, bs, bn, x0, x1, y0, y1, cx, cy, cf)
                if cn < 3:
                    continue
                piece_integrals(cx, cy, cs, cn, float(col), float(row), kind, radius, k, alpha, bias, out)
                for a in range(k):
                    for b in range(k):
                        for c in range(nch):
                            acc[row, col, a, b, c] += weights[r, c] * out[a, b]


def cell_basis_matrix(filt: PixelFilter) -> np.ndarray:
    """``E[p + R, a]``: pixel weight of basis function ``a`` for the piece ``p`` of the filter.

    Polynomial: the cell-local coefficients; Gaussian: the identity (its basis functions
    are the shifted profiles themselves).
    """
    if filt.kind == KIND_GAUSSIAN:
        return np.eye(2 * filt.knot_radius)
    return np.asarray(filt.pieces, dtype=np.float64)


def combine_cells(acc: np.ndarray, filt: PixelFilter, width: int, height: int) -> np.ndarray:
    """Pixel sums ``(H, W, channels)`` from cell accumulators ``(H+1, W+1, k, k, channels)``.

    Pixel ``i`` takes piece ``p = m - i - 1`` of the filter from cell ``m``
    (``p = -R .. R-1``); separable, so x is contracted first, then y.
    """
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
