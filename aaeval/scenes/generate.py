"""Small generators of test and benchmark scenes."""

from __future__ import annotations

import numpy as np

from aaeval.scenes.format import Scene, parse_scene

__all__ = ["random_triangles"]


def random_triangles(
    width: int,
    height: int,
    n: int,
    *,
    seed: int = 0,
    size: float = 30.0,
    tilt: float = 0.05,
    background=(0.0, 0.0, 0.0),
) -> Scene:
    """``n`` random flat-coloured triangles over a ``width x height`` image.

    Each triangle's vertices lie within ``size`` pixels of a centre drawn uniformly over
    the image (so some reach outside it); its depth plane has a random mean depth in
    [0, 10) and slopes up to ``tilt`` per pixel, so triangles overlap and interpenetrate.
    Colours are uniform in [0, 1)^3. Reproducible from ``seed``.
    """
    rng = np.random.default_rng(seed)
    centres = rng.uniform([0, 0], [width, height], size=(n, 1, 2))
    xy = centres + rng.uniform(-size, size, size=(n, 3, 2))
    depth = rng.uniform(0, 10, size=(n, 1)) + np.einsum(
        "nk,nvk->nv", rng.uniform(-tilt, tilt, size=(n, 2)), xy - centres
    )
    colors = rng.uniform(0, 1, size=(n, 3))
    polygons = [
        {"color": colors[i].tolist(), "vertices": np.column_stack([xy[i], depth[i]]).tolist()}
        for i in range(n)
    ]
    document = {"image": {"width": width, "height": height, "background": list(background)}, "polygons": polygons}
    return parse_scene(document, source=f"<random_triangles {width}x{height} n={n} seed={seed}>")
