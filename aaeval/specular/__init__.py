"""Specular aliasing (Amanatides 1992): detection, clamping, and today's alternatives.

- :mod:`aaeval.specular.tables`: Fourier tables of cos^n (``power_cutoff``, MinDot,
  Maximum, MaxnAllowed), from exact binomial coefficients;
- :mod:`aaeval.specular.shading`: the one Phong formula, corner-normal detection, every
  exponent clamp (Amanatides, Toksvig, Vlachos, Tokuyoshi-Kaplanyan);
- :mod:`aaeval.specular.render`: shaded rendering by Catmull visibility (method
  ``catmull:specular=...``) and :func:`specular_aliasing_map`;
- :mod:`aaeval.specular.groundtruth`: the Mitsuba Phong ground truth (method ``mitsuba``
  on ``[shaded]`` scenes).

Scenes: the ``[shaded]`` extension, :mod:`aaeval.scenes.shaded` (docs/shaded_scenes.md).
"""

from aaeval.specular.render import SPECULAR_METHODS, AliasingMap, render_shaded, specular_aliasing_map
from aaeval.specular.shading import phong, specular_term
from aaeval.specular.tables import max_n_allowed, maximum, min_dot, power_cutoff, power_spectrum

__all__ = [
    "SPECULAR_METHODS",
    "AliasingMap",
    "render_shaded",
    "specular_aliasing_map",
    "phong",
    "specular_term",
    "power_cutoff",
    "power_spectrum",
    "min_dot",
    "maximum",
    "max_n_allowed",
]
