"""Specular aliasing (Amanatides 1992): detection, clamping, and today's alternatives.

- :mod:`aaeval.specular.tables`: Fourier tables of cos^n (``power_cutoff``, MinDot,
  Maximum, MaxnAllowed), from exact binomial coefficients;
- :mod:`aaeval.specular.shading`: the one Phong formula, corner-normal detection, every
  exponent clamp (Amanatides, Toksvig, Vlachos, Tokuyoshi-Kaplanyan);
- :mod:`aaeval.specular.methods`: the registry of specular methods and their parameters,
  which the method ``catmull:specular=...`` reads (register a clamp there, nowhere else);
- :mod:`aaeval.specular.render`: shaded rendering by Catmull visibility and
  :func:`specular_aliasing_map`.

The Mitsuba Phong ground truth is :mod:`aaeval.groundtruth.phong`. Scenes: the
``[shaded]`` extension, :mod:`aaeval.scenes.shaded` (docs/shaded_scenes.md).

The names below are loaded on first use: :mod:`aaeval.renderers.catmull` imports
:mod:`aaeval.specular.methods` at load time, and :mod:`aaeval.specular.render` uses
Catmull's visibility, so this package must not import ``render`` when it is loaded.
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "SPECULAR_METHODS": "aaeval.specular.methods",
    "register_specular": "aaeval.specular.methods",
    "AliasingMap": "aaeval.specular.render",
    "render_shaded": "aaeval.specular.render",
    "specular_aliasing_map": "aaeval.specular.render",
    "phong": "aaeval.specular.shading",
    "specular_term": "aaeval.specular.shading",
    "power_cutoff": "aaeval.specular.tables",
    "power_spectrum": "aaeval.specular.tables",
    "min_dot": "aaeval.specular.tables",
    "maximum": "aaeval.specular.tables",
    "max_n_allowed": "aaeval.specular.tables",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'aaeval.specular' has no attribute {name!r}")
