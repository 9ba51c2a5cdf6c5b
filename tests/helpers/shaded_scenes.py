"""Small shaded scenes the specular tests share, with the geometry written out by hand."""

from __future__ import annotations

import math

import numpy as np

MATERIAL = {"color": [0.7, 0.2, 0.1], "ka": 0.1, "kd": 0.5, "ks": 0.8, "n": 200}
LIGHT = [0.2, -0.1, -1.0]


def small_scene(light=None, frames=1, spin=0.0, translate=(0.0, 0.0)):
    """A 24 x 20 scene: a flat backdrop square, a shiny cylinder and a cone in front."""
    return {
        "image": {"width": 24, "height": 20, "background": [0.05, 0.05, 0.05]},
        "animation": {"frames": frames, "translate": list(translate)},
        "polygons": [{"color": [0.1, 0.3, 0.1], "vertices": [[1, 1, 50], [23, 2, 50], [22, 19, 50], [2, 18, 50]]}],
        "shaded": {
            "light": light or {"type": "directional", "direction": LIGHT},
            "cylinders": [
                {
                    "centre": [9.3, 10.2, 20.0], "axis": [0.2, 1.0, 0.1], "radius": 4.5, "length": 15.0,
                    "segments": 24, "material": MATERIAL,
                    "spin": {"axis": [0.0, 0.0, 1.0], "degrees": spin},
                }
            ],
            "cones": [
                {"centre": [18.4, 9.7, 25.0], "axis": [0.1, -1.0, -0.2], "radii": [3.5, 0.0], "length": 14.0,
                 "segments": 16, "material": {**MATERIAL, "n": 60}}
            ],
        },
    }


W, H = 28, 24
CX, CY, RADIUS, LENGTH = 13.37, 12.0, 9.0, 20.0
N_EXPONENT, KS = 200.0, 0.8


def cylinder_document(*, light=None, n=N_EXPONENT, segments=512):
    """A vertical cylinder (axis +y) seen side-on: its normal turns only along x."""
    return {
        "image": {"width": W, "height": H, "background": [0.0, 0.0, 0.0]},
        "shaded": {
            "light": light or {"type": "directional", "direction": [0.5, 0.0, -1.0]},
            "cylinders": [{
                "centre": [CX, CY, 50.0], "axis": [0.0, 1.0, 0.0], "radius": RADIUS, "length": LENGTH,
                "segments": segments, "caps": False,
                "material": {"color": [0.6, 0.3, 0.2], "ka": 0.1, "kd": 0.5, "ks": KS, "n": n},
            }],
        },
    }


def half_vector_column() -> float:
    """Directional light: the peak column is where N = normalize(L + E), E = (0, 0, -1)."""
    light = np.array([0.5, 0.0, -1.0]) / math.hypot(0.5, 1.0)
    half = light + np.array([0.0, 0.0, -1.0])
    half /= np.linalg.norm(half)
    return CX + RADIUS * half[0]  # the circle's normal (u, 0, -sqrt(1-u^2)) equals H at u = H_x
