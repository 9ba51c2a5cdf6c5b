"""Digests of the Weiler-Atherton clipper's and solver's own outputs
(``tests/data/same_bits_wa_clipper.json``).

The image digests of ``tests/helpers/same_bits.py`` see the clipper only through the box filter;
these look at its arrays directly: ``clip_arrays`` on random polygon pairs (integer-grid
stars with shared vertices, vertices on edges and collinear overlaps; float stars with
holes; rotated copies), ``first_crossing``, ``half_plane``, ``later_neighbours``, the
solver's flat visible pieces on the regression's random, degenerate and near-tie scenes
(both roads, with and without screen subdivision), ``near_ties.resolve_flat_arrays`` on
the near-tie stacks, and the box filter's coverage.

The clipper's, crossings', half-planes', neighbours', near-tie rule's and coverage entries are
the numba kernels' arrays, which the native ones reproduce bit for bit: never record those
from the native kernels. The solver's visible pieces (``visible-*``) were recorded from the
native solver (``python3 -m tests.helpers.same_bits_wa_clipper record``, then every entry
but those compared unchanged) once its one loop replaced the chain of pieces per polygon,
which cut pieces differently: each changed case's pieces, box-filtered, agreed with the GEOS
oracle (``tests/helpers/oracle.py``) and with catmull within 4e-15.
"""

from __future__ import annotations

import hashlib
import json
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "data"
RECORD = DATA / "same_bits_wa_clipper.json"


def digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(f"{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _star(rng, centre, r_lo, r_hi, n, grid=False):
    angles = 2 * np.pi * (np.arange(n) + rng.uniform(0.0, 0.9, n)) / n
    radii = rng.uniform(r_lo, r_hi, n)
    xy = np.column_stack([centre[0] + radii * np.cos(angles), centre[1] + radii * np.sin(angles)])
    if grid:
        xy = np.round(xy)
    return xy


def _shape(rings, label):
    """Flat arrays of contours, the first made positive, the rest negative."""
    from aaeval.weiler_atherton.clipper import oriented, to_arrays

    shape = oriented([[tuple(p) for p in r] for r in rings], label)
    for r in shape.rings:
        if len(r) < 3:
            return None
    return to_arrays(shape)


def _pairs(seed: int, first_crossing):
    """A random subject and clip shape (flat arrays), or None where one is degenerate."""
    rng = np.random.default_rng(seed)
    kind = seed % 4
    grid = kind in (0, 1)
    shapes = []
    for label in (1, 2):
        c = rng.uniform(2, 6, 2)
        if grid:
            c = np.round(c)
        outer = _star(rng, c, 1.0, 5.0, int(rng.integers(3, 10)), grid)
        rings = [outer]
        if kind in (1, 2) and rng.random() < 0.6:
            rings.append(_star(rng, c, 0.2, 0.9, int(rng.integers(3, 6)), False))
        if kind == 3:
            a = rng.uniform(0, 2 * np.pi)
            rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            rings = [r @ rot.T * 1e3 + 1e4 for r in rings]
        arrays = _shape(rings, label)
        if arrays is None:
            return None
        xs, ys, _, starts = arrays
        m = max(1.0, float(np.abs(xs).max()), float(np.abs(ys).max()))
        if first_crossing(xs, ys, starts, 2e-14 * m)[0] >= 0:
            return None
        shapes.append(arrays)
    if seed % 7 == 3:  # a clip shape sharing the subject's vertices: shared edges
        xs, ys, lab, st = shapes[0]
        shapes[1] = (xs[::-1].copy() + 0.0, ys[::-1].copy(), np.full(len(xs), 2, np.int64), st)
        if _area(shapes[1][0], shapes[1][1]) < 0:
            shapes[1] = (xs.copy(), ys.copy(), np.full(len(xs), 2, np.int64), st)
    m = max(1.0, *(float(np.abs(a).max()) for s in shapes for a in s[:2]))
    return shapes[0], shapes[1], 2e-14 * m


def kernels() -> dict:
    """The functions the digests are taken of, as the package has them now."""
    from aaeval.native.weiler_atherton import clip_arrays, first_crossing, later_neighbours
    from aaeval.native.weiler_atherton_testing import half_plane
    from aaeval.weiler_atherton import visible_arrays
    from aaeval.weiler_atherton.near_ties import resolve_flat_arrays
    from aaeval.weiler_atherton.raster import coverage_flat

    return dict(clip_arrays=clip_arrays, first_crossing=first_crossing, half_plane=half_plane,
                later_neighbours=later_neighbours, visible_arrays=visible_arrays,
                resolve_flat_arrays=resolve_flat_arrays, coverage_flat=coverage_flat)


def _resolved(scene, resolve_flat_arrays):
    """``near_ties.resolve_flat_arrays`` of the scene's polygons, as catmull calls it."""
    from aaeval.scenes.depth import depth_tolerance

    arr = scene.arrays
    xy = arr.vertices[:, :2]
    return resolve_flat_arrays(np.asarray(arr.start, np.int64), np.asarray(arr.length, np.int64),
                               np.ascontiguousarray(xy[:, 0], dtype=np.float64),
                               np.ascontiguousarray(xy[:, 1], dtype=np.float64),
                               np.ascontiguousarray(arr.planes, dtype=np.float64),
                               np.arange(len(arr.start), dtype=np.int64), depth_tolerance(arr.vertices[:, 2]))


def tie_stacks():
    """Near-coplanar stacks the rule resolves (``tests/catmull/test_depth_ties.py``'s kinds): one
    quad tilted k times about a pivot, and a square with one corner raised by i * 1e-12."""
    from aaeval.scenes import parse_scene

    quad = [(5.25, 6.5), (57.75, 4.125), (59.5, 58.25), (3.125, 55.875)]
    for k, tilt, seed in ((3, 1e-12, 0), (4, 1e-11, 1), (6, 1e-10, 2), (12, 1e-12, 3), (12, 1e-9, 4), (30, 1e-12, 5)):
        rng = np.random.default_rng(seed)
        theta = rng.uniform(0, 2 * np.pi, k)
        polys = [{"color": rng.uniform(0, 1, 3).tolist(),
                  "vertices": [[x, y, 1.0 + tilt * np.cos(t) * (x - 31.0) + tilt * np.sin(t) * (y - 31.0)]
                               for x, y in quad]} for t in theta]
        yield f"stack-{k}-{tilt}-{seed}", parse_scene({"image": {"width": 64, "height": 64}, "polygons": polys})
    square = [[4, 4], [40, 5], [39, 40], [3, 41]]
    for k in (3, 20):
        polys = [{"color": [1.0, 0.0, 0.0],
                  "vertices": [[*square[0], 1 + i * 1e-12], [*square[1], 1], [*square[2], 1], [*square[3], 1]]}
                 for i in range(k)]
        yield f"squares-{k}", parse_scene({"image": {"width": 41, "height": 41}, "polygons": polys})


def _area(xs, ys) -> float:
    return 0.5 * float(np.sum(xs * np.roll(ys, -1) - np.roll(xs, -1) * ys))


def cases(k: dict | None = None) -> Iterator[tuple[str, str]]:
    """``(case id, digest)`` of every case, the functions taken from ``k`` (default: :func:`kernels`)."""
    from tests.helpers.randomscenes import degenerate_scene, random_scene
    from tests.helpers.same_bits import near_tie_stack

    k = kernels() if k is None else k
    clip_arrays, first_crossing, half_plane = k["clip_arrays"], k["first_crossing"], k["half_plane"]
    later_neighbours, visible_arrays = k["later_neighbours"], k["visible_arrays"]
    resolve_flat_arrays, coverage_flat = k["resolve_flat_arrays"], k["coverage_flat"]

    for seed in range(400):
        pair = _pairs(seed, first_crossing)
        if pair is None:
            continue
        s, c, eps = pair
        yield f"clip-{seed}", digest(*clip_arrays(*s, *c, eps))
        yield f"clip-swapped-{seed}", digest(*clip_arrays(*c, *s, eps))
        yield f"crossing-{seed}", digest(np.array(first_crossing(s[0], s[1], s[3], eps)))
    rng = np.random.default_rng(5)
    for k in range(40):
        a, b, c = rng.normal(size=3)
        if k % 5 == 0:
            a = 0.0
        box = np.sort(rng.uniform(-3, 3, 2)).tolist() + np.sort(rng.uniform(-3, 3, 2)).tolist()
        box = np.array([box[0], box[2], box[1], box[3]])
        yield f"half-plane-{k}", digest(*half_plane(a, b, c, box))
    for k in range(20):
        n = int(rng.integers(1, 60))
        lo = rng.uniform(0, 20, (n, 2))
        boxes = np.column_stack([lo, lo + rng.uniform(0, 6, (n, 2))])
        if k % 3 == 0:
            boxes = np.round(boxes)
        order = rng.permutation(n).astype(np.int64)
        yield f"neighbours-{k}", digest(*later_neighbours(boxes, order))
    scenes = [(f"random-{s}", lambda s=s: random_scene(s, tilt=0.0 if s % 5 == 0 else 1.0)) for s in range(40)]
    scenes += [(f"degenerate-{s}", lambda s=s: degenerate_scene(s)) for s in range(30)]
    scenes += [(f"near-tie-{s}", lambda s=s: near_tie_stack(s, k=2 + s % 4)) for s in range(10)]
    for name, make in scenes:
        scene = make()
        for convex in (True, False):
            for window in (0, 3):
                yield f"visible-{name}-{convex}-{window}", digest(*visible_arrays(scene, window=window, convex=convex))
        yield f"resolve-{name}", digest(*_resolved(scene, resolve_flat_arrays))
    for name, scene in tie_stacks():  # stacks the near-tie rule resolves (the clipper's heaviest use)
        yield f"visible-{name}", digest(*visible_arrays(scene))
        yield f"resolve-{name}", digest(*_resolved(scene, resolve_flat_arrays))
    for k in range(20):
        nr = int(rng.integers(1, 5))
        rings = [_star(rng, rng.uniform(-2, 12, 2), 0.5, 6, int(rng.integers(3, 12))) for _ in range(nr)]
        lengths = np.array([len(r) for r in rings], np.int64)
        starts = np.zeros(nr + 1, np.int64)
        np.cumsum(lengths, out=starts[1:])
        xy = np.concatenate(rings)
        w = rng.normal(size=(nr, 3))
        yield f"coverage-{k}", digest(coverage_flat(xy[:, 0].copy(), xy[:, 1].copy(), starts, w, 11, 9))


def record() -> Path:
    RECORD.write_text(json.dumps(dict(cases()), indent=1, sort_keys=True) + "\n")
    return RECORD


if __name__ == "__main__":
    if sys.argv[1:] != ["record"]:
        raise SystemExit("usage: python3 -m tests.helpers.same_bits_wa_clipper record")
    print(record())
