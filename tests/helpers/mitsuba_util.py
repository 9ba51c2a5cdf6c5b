"""A mixed scene and the seed-noise statistics the Mitsuba tests share."""

from __future__ import annotations

import numpy as np

from aaeval.groundtruth import flat as gt
from aaeval.renderers import render
from aaeval.scenes import parse_scene


def poly(color, xy, a=0.0, b=0.0, c=0.0):
    """A polygon on the depth plane z = a x + b y + c."""
    return {"color": color, "vertices": [[x, y, a * x + b * y + c] for x, y in xy]}


def mixed_scene(width=32, height=24):
    """Shipped-scene kinds of content, scaled to the image: overlap, interpenetration,
    a concave outline, polygons reaching far outside, a coplanar pair, both windings."""
    sx, sy = width / 32, height / 24

    def s(points):
        return [[x * sx, y * sy] for x, y in points]

    return parse_scene(
        {
            "image": {"width": width, "height": height, "background": [0.1, 0.2, 0.3]},
            "polygons": [
                poly([1, 0, 0], s([[-5, -3], [20, 2], [10, 30]]), 0.1, 0.05, 5),
                poly([0, 1, 0], s([[3, 3], [28, 5], [30, 20], [16, 8], [2, 21]]), 0.3, 0.0, 1),  # concave
                poly([0, 0, 1], s([[0, 12.3], [40, 11.6], [40, 14.2], [0, 14.7]]), 0.0, 2.0, -20),  # crosses both
                poly([1, 1, 0], s([[4.5, 4.2], [12.3, 4.7], [11.8, 10.1], [4.1, 9.6]]), 0.1, 0.05, 5),  # on plane of 0
                poly([0.5, 0.25, 1], s([[31.5, -100], [1e5, 22.7], [26.2, 23.1]]), 0.0, 0.0, -50),  # far outside
                poly([0.9, 0.6, 0.2], s([[20, 15], [20, 23], [29, 23], [29, 15], [26, 15], [26, 20], [23, 20], [23, 15]])[::-1], 0.0, 0.0, 0.5),
            ],
        },
        source="<mixed>",
    )


def exact(scene):
    return render(scene, "catmull")


def seeds(scene, n, *, spp, sampler="stratified"):
    return np.stack([gt.render_mitsuba(scene, spp=spp, sampler=sampler, seed=k) for k in range(n)])


def noise_statistics(images, reference):
    """(mean squared error of one render, of the mean, predicted one-render variance).

    The per-pixel variance is estimated from the spread between seeds; if Mitsuba is
    unbiased, a single render's MSE is about the mean variance and the seed average's
    MSE about the mean variance / number of seeds.
    """
    k = len(images)
    variance = images.var(axis=0, ddof=1).mean()
    single = np.mean((images - reference) ** 2)
    averaged = np.mean((images.mean(axis=0) - reference) ** 2)
    return single, averaged, variance, k


# float32 colours and coordinates in Mitsuba: far below any sampling noise here
FLOAT32_FLOOR = 1e-12
