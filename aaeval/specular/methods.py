"""The specular methods of ``catmull:specular=NAME`` and their parameters: one registry.

This module is the only place a specular method or one of its parameters is known. The
Catmull method builds its options from :data:`PARAMETERS` (the ``specular`` option's
choices are the live keys of :data:`SPECULAR_METHODS`), so a method registered here, by
anyone, at any time, is accepted by ``catmull:specular=NAME`` with no other edit::

    from aaeval.specular.methods import register_specular

    def halve(corners, n, **options):   # corners: (k, 4, 3) unit normals, n: (k,)
        return n / 2

    register_specular("halve", summary="half the exponent everywhere", clamp=halve)

A *clamp* maps, per visible shaded piece of a polygon in a pixel, the unit normals at
the pixel's four corners (order 00, 10, 01, 11) and the Phong exponent to a new exponent
``n'``; it is called with every other option as a keyword (``power``, ``k``, ``region``,
``energy``) and reads the ones it needs. The renderer keeps ``n' <= n`` and rescales
``ks`` by ``Maximum[n] / Maximum[n']`` unless ``energy="none"``. A method without a clamp
keeps n and ks; ``supersample=True`` (Crow) also shades Amanatides' flagged pieces (or all
of them) on a K x K grid.

This module imports nothing from :mod:`aaeval.renderers` (which imports it); the specular
methods of other packages register through :func:`aaeval.registries.load`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from aaeval.options import Option, Registry
from aaeval.specular.shading import (
    clamp_amanatides,
    clamp_tokuyoshi,
    clamp_toksvig,
    clamp_vlachos,
    min_corner_dot,
)

__all__ = [
    "SpecularMethod",
    "PARAMETERS",
    "SPECULAR_METHODS",
    "register_specular",
    "specular_options",
]


@dataclass(frozen=True)
class SpecularMethod:
    """A registered specular method (see the module docstring for ``clamp``)."""

    name: str
    summary: str
    clamp: Callable[..., np.ndarray] | None = None
    supersample: bool = False


SPECULAR_METHODS: Registry = Registry("specular method")


def register_specular(
    name: str, *, summary: str, clamp: Callable[..., np.ndarray] | None = None, supersample: bool = False
) -> SpecularMethod:
    """Register a specular method under ``name``; refuses a name registered twice."""
    if not isinstance(name, str) or not name or any(c in name for c in ",:= "):
        raise ValueError(f"specular method name {name!r} must be a non-empty word (no ',', ':', '=' or spaces)")
    return SPECULAR_METHODS.add(name, SpecularMethod(name, summary, clamp, supersample))


PARAMETERS: dict[str, Option] = {
    "specular": Option(
        str,
        "none",
        "shading of [shaded] objects: a specular method registered in aaeval.specular.methods "
        "(none = plain Phong, one shade per visible piece)",
        choices=SPECULAR_METHODS.keys(),  # a live view: methods registered later are accepted
    ),
    "power": Option(
        float,
        1.0,
        "amanatides/crow: fraction of the power of cos^n kept by the tables; 1 = the "
        "conservative form, 0.999 = the paper's aggressive plate",
        minimum=1e-6,
        maximum=1.0,  # a fraction of the power (aaeval.specular.tables refuses more)
    ),
    "k": Option(int, 4, "crow: K x K shading samples per supersampled piece", minimum=1),
    "region": Option(str, "flagged", "crow: supersample flagged pieces or all", choices=("flagged", "all")),
    "energy": Option(
        str,
        "amanatides",
        "every clamp: rescale ks by Maximum[n]/Maximum[n'] (Amanatides) or keep it (none)",
        choices=("amanatides", "none"),
    ),
}


def specular_options(**options: Any) -> dict[str, Any]:
    """Every parameter, defaults filled in; unknown names and unregistered methods refused.

    The Catmull method's spec validation does types and ranges; this check is for direct
    callers of :func:`aaeval.specular.render.render_shaded`.
    """
    unknown = sorted(set(options) - set(PARAMETERS))
    if unknown:
        raise ValueError(f"unknown specular option(s) {unknown}; options: {sorted(PARAMETERS)}")
    full = {name: p.default for name, p in PARAMETERS.items()}
    full.update(options)
    return {name: PARAMETERS[name].convert(value, f"specular option {name}", ValueError) for name, value in full.items()}


def _amanatides(corners: np.ndarray, n: np.ndarray, *, power: float, **_: Any) -> np.ndarray:
    """Amanatides 1992: ``n' = MaxnAllowed[pi / (2 acos(dot))]`` where dot < MinDot[n]."""
    n_new, _, _ = clamp_amanatides(min_corner_dot(corners), n, np.ones_like(n), power=power)
    return n_new


register_specular("none", summary="plain Phong, one shade per visible piece")
register_specular("amanatides", summary="Amanatides 1992: exponent clamped where the normal turns too fast",
                  clamp=_amanatides)
register_specular("crow", summary="Crow: K x K shading samples in Amanatides' flagged pieces", supersample=True)
register_specular("toksvig", summary="Toksvig 2005: roughness from the shortened mean normal",
                  clamp=clamp_toksvig)
register_specular("vlachos", summary="Vlachos 2015: roughness from the normal's screen derivatives",
                  clamp=clamp_vlachos)
register_specular("tokuyoshi", summary="Tokuyoshi & Kaplanyan 2021: roughness variance from derivatives",
                  clamp=clamp_tokuyoshi)

