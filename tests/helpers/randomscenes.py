"""Random scenes for tests: interpenetrating triangles, concave stars, degenerate placements."""

from __future__ import annotations

import numpy as np

from aaeval.scenes import parse_scene


def star(rng, centre, r_lo, r_hi, n):
    """A random star-shaped (so simple, usually concave) outline around centre."""
    # jittered even angles keep every gap below pi, so the outline is star-shaped
    angles = 2 * np.pi * (np.arange(n) + rng.uniform(0.0, 0.9, n)) / n
    radii = rng.uniform(r_lo, r_hi, n)
    return np.column_stack([centre[0] + radii * np.cos(angles), centre[1] + radii * np.sin(angles)])


def with_plane(xy, rng, tilt=1.0, depth=(0.0, 10.0)):
    a, b = rng.uniform(-tilt, tilt, 2)
    c = rng.uniform(*depth)
    z = a * xy[:, 0] + b * xy[:, 1] + c
    return np.column_stack([xy, z]).tolist()


def random_scene(seed, width=14, height=11, n_tri=5, n_star=2, tilt=1.0):
    rng = np.random.default_rng(seed)
    polys = []
    for _ in range(n_tri):
        centre = rng.uniform([-2, -2], [width + 2, height + 2])
        xy = centre + rng.uniform(-6, 6, (3, 2))
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": with_plane(xy, rng, tilt)})
    for _ in range(n_star):
        centre = rng.uniform([0, 0], [width, height])
        xy = star(rng, centre, 0.8, 6.0, int(rng.integers(5, 11)))
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": with_plane(xy, rng, tilt)})
    doc = {
        "image": {"width": width, "height": height, "background": rng.uniform(0, 1, 3).tolist()},
        "polygons": polys,
    }
    return parse_scene(doc, source=f"<random {seed}>")


def degenerate_scene(seed):
    """Shared vertices, edges on pixel boundaries, abutting mesh triangles, equal depths."""
    rng = np.random.default_rng(seed)
    width, height = int(rng.integers(3, 12)), int(rng.integers(3, 12))
    polys = []
    for k in range(int(rng.integers(2, 12))):
        if seed % 2 == 0:  # half-integer vertices: edges along pixel boundaries, shared vertices
            xy = rng.integers(-2, 2 * width + 2, (3, 2)) / 2.0
        else:  # pairs of triangles sharing a diagonal, as in a mesh
            i, j, s = rng.integers(0, width), rng.integers(0, height), rng.uniform(0.5, 3)
            xy = np.array([[i, j], [i + s, j], [i, j + s]]) if k % 2 else np.array([[i + s, j], [i + s, j + s], [i, j + s]])
        x, y = xy[:, 0], xy[:, 1]
        if abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) < 1e-9:
            continue
        a, b = rng.uniform(-2, 2, 2) if rng.random() < 0.7 else (0.0, 0.0)
        z = a * x + b * y + float(rng.integers(0, 4))  # small integer depths: many shared planes
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": np.column_stack([xy, z]).tolist()})
    return parse_scene({"image": {"width": width, "height": height}, "polygons": polys})


def holed_polygon(rng, centre, n_holes, tilt=1.0):
    """A random star-shaped outer ring with ``n_holes`` random star-shaped holes inside.

    The outer ring's vertices are at radius >= 4 with angular gaps < 1 rad, so its edges
    stay beyond radius 3.5; holes of radius <= 1 centred at radius 1.7, one per sector of
    a circle split in three, stay inside radius 2.7 and apart from each other.
    """
    outer = star(rng, centre, 4.0, 6.5, 12)
    start = rng.uniform(0, 2 * np.pi)
    holes = []
    for m in range(n_holes):
        angle = start + 2 * np.pi * m / 3
        c = centre + 1.7 * np.array([np.cos(angle), np.sin(angle)])
        holes.append(star(rng, c, 0.3, 0.95, int(rng.integers(3, 8))))
    a, b = rng.uniform(-tilt, tilt, 2)
    depth = rng.uniform(0, 10)

    def lift(xy):
        return np.column_stack([xy, a * xy[:, 0] + b * xy[:, 1] + depth]).tolist()

    return {"color": rng.uniform(0, 1, 3).tolist(), "vertices": lift(outer), "holes": [lift(h) for h in holes]}


def random_holed_document(seed, width=16, height=12):
    rng = np.random.default_rng(seed)
    polygons = []
    for _ in range(3):
        centre = rng.uniform([1, 1], [width - 1, height - 1])
        polygons.append(holed_polygon(rng, centre, int(rng.integers(1, 4))))
    for _ in range(2):
        xy = rng.uniform([-2, -2], [width + 2, height + 2]) + rng.uniform(-6, 6, (3, 2))
        polygons.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": with_plane(xy, rng)})
    rng.shuffle(polygons)
    doc = {"image": {"width": width, "height": height, "background": rng.uniform(0, 1, 3).tolist()},
           "polygons": polygons, "animation": {"frames": 3, "translate": [0.37, -0.21]}}
    return doc


def random_holed_scene(seed, width=16, height=12):
    return parse_scene(random_holed_document(seed, width, height), source=f"<holed {seed}>")
