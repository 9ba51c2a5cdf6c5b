"""The one Phong formula, Amanatides' detection, and every exponent clamp.

Shading (written once, used by the Catmull renderer, the Mitsuba integrator and tests)::

    I = C (ka + kd max(N.L, 0)) + ks max(R.E, 0)^n,   R = 2 (N.L) N - L

with N the unit surface normal, L the unit vector toward the light, E = (0, 0, -1) the
unit vector toward the (orthographic) viewer. The specular term is white (added to all
three channels) and is not gated by N.L, exactly as written.

Clamps (``n' <= n``, applied per visible piece of a polygon in a pixel):

- ``amanatides`` (Amanatides 1992): where the smallest corner-normal dot product is below
  MinDot[n], ``sampleFrequency = pi / (2 acos(dot))`` and ``n' = MaxnAllowed[f]``
  (``n' = f`` in the conservative form, power = 1), ``ks' = ks Maximum[n] / Maximum[n']``.
- ``toksvig`` (Toksvig 2005), ``vlachos`` (Vlachos 2015), ``tokuyoshi`` (Tokuyoshi &
  Kaplanyan 2021): roughness widened from the normal's variation over the pixel, mapped
  to the Phong lobe by n_blinn = 4 n and alpha = sqrt(2 / (n_blinn + 2)) (Walter et al.
  2007); ks rescaled like Amanatides' (``energy="amanatides"``) or kept (``"none"``).
"""

from __future__ import annotations

import numpy as np

from aaeval.scenes.shaded import EYE
from aaeval.specular.tables import max_n_allowed, maximum, min_dot

__all__ = [
    "phong",
    "specular_term",
    "corner_offsets",
    "min_corner_dot",
    "normal_derivatives",
    "amanatides_rate",
    "clamp_amanatides",
    "clamp_toksvig",
    "clamp_vlachos",
    "clamp_tokuyoshi",
    "exponent_to_alpha2",
    "alpha2_to_exponent",
    "rescale_ks",
]

# Tokuyoshi & Kaplanyan 2021 (author's code, per the field notes): variance scale and clamp
TOKUYOSHI_K = 1.0 / (2.0 * np.pi)
TOKUYOSHI_KAPPA = 0.18

# pixel corners (dx, dy) in the order 00, 10, 01, 11
corner_offsets = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])


def specular_term(N: np.ndarray, L: np.ndarray, ks, n) -> np.ndarray:
    """``ks max(R.E, 0)^n`` with ``R = 2 (N.L) N - L``, E toward the viewer; shape (k,)."""
    ndotl = np.einsum("ij,ij->i", N, L)
    R = 2.0 * ndotl[:, None] * N - L
    rdote = np.maximum(R[:, 0] * EYE[0] + R[:, 1] * EYE[1] + R[:, 2] * EYE[2], 0.0)  # no BLAS: same bits on every CPU
    with np.errstate(divide="ignore", invalid="ignore"):
        lobe = np.where(np.asarray(n) == 0, 1.0, rdote ** np.asarray(n, dtype=np.float64))
    return np.asarray(ks) * lobe


def phong(N, L, color, ka, kd, ks, n) -> tuple[np.ndarray, np.ndarray]:
    """The Phong formula at k points: returns ``(rgb (k, 3), specular (k,))``.

    ``N`` and ``L`` are unit vectors (k, 3); ``color`` is (k, 3) or (3,); the scalars
    broadcast over k.
    """
    N = np.atleast_2d(np.asarray(N, dtype=np.float64))
    L = np.atleast_2d(np.asarray(L, dtype=np.float64))
    diffuse = np.maximum(np.einsum("ij,ij->i", N, L), 0.0)
    spec = specular_term(N, L, ks, n)
    rgb = np.asarray(color) * (np.asarray(ka) + np.asarray(kd) * diffuse)[:, None] + spec[:, None]
    return rgb, spec


# --- how much the normal turns in a pixel ------------------------------------------


def min_corner_dot(corners: np.ndarray) -> np.ndarray:
    """Smallest of the six pairwise dot products of four unit normals (k, 4, 3) -> (k,)."""
    i, j = np.triu_indices(4, k=1)
    dots = np.einsum("kpc,kpc->kp", corners[:, i], corners[:, j])
    return np.clip(dots.min(axis=1), -1.0, 1.0)


def normal_derivatives(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Screen-space derivatives of the unit normal across a pixel: (dn/dx, dn/dy), (k, 3) each."""
    c00, c10, c01, c11 = corners[:, 0], corners[:, 1], corners[:, 2], corners[:, 3]
    return 0.5 * ((c10 - c00) + (c11 - c01)), 0.5 * ((c01 - c00) + (c11 - c10))


def amanatides_rate(dot: np.ndarray, n: np.ndarray, power: float = 1.0) -> np.ndarray:
    """Oversampling rate ``delta_alpha_N / delta_alpha_n``; above 1 exactly where dot < MinDot.

    ``delta_alpha_N = 2 acos(dot)`` is how much alpha turns in the pixel and
    ``delta_alpha_n = pi / f`` the largest safe step, f the (power) cutoff of cos^n.
    """
    f_n = _cutoff_frequency(n, power)
    return 2.0 * np.arccos(np.clip(dot, -1.0, 1.0)) * f_n / np.pi


def _cutoff_frequency(n, power: float) -> np.ndarray:
    # min_dot(n, power) = cos(pi / (2 f)) -> f = pi / (2 acos(min_dot))
    md = min_dot(n, power)
    with np.errstate(divide="ignore"):
        return np.where(md >= 1.0, np.inf, np.pi / (2.0 * np.arccos(np.clip(md, -1.0, 1.0))))


def clamp_amanatides(dot: np.ndarray, n: np.ndarray, ks: np.ndarray, *, power: float = 1.0):
    """Amanatides' clamp. Returns ``(n', ks', flagged)``; unflagged pieces keep n and ks."""
    n = np.asarray(n, dtype=np.float64)
    ks = np.asarray(ks, dtype=np.float64)
    flagged = dot < min_dot(n, power)
    n_new = n.copy()
    if flagged.any():
        turn = np.arccos(np.clip(dot[flagged], -1.0, 1.0))  # acos(dot) > 0 where flagged
        frequency = np.pi / (2.0 * turn)
        n_max = int(np.ceil(n[flagged].max()))
        n_new[flagged] = np.minimum(max_n_allowed(frequency, power, n_max), n[flagged])
    return n_new, rescale_ks(ks, n, n_new), flagged


def rescale_ks(ks, n, n_new) -> np.ndarray:
    """``ks Maximum[n] / Maximum[n']``: the clamped lobe keeps the original DC level."""
    return np.asarray(ks) * maximum(n) / maximum(n_new)


def exponent_to_alpha2(n) -> np.ndarray:
    """Phong exponent (reflection lobe) -> squared GGX/Beckmann roughness: 2 / (4 n + 2)."""
    return 2.0 / (4.0 * np.asarray(n, dtype=np.float64) + 2.0)


def alpha2_to_exponent(alpha2) -> np.ndarray:
    """Inverse of :func:`exponent_to_alpha2`: n = (2 / alpha^2 - 2) / 4, at least 0."""
    return np.maximum((2.0 / np.asarray(alpha2, dtype=np.float64) - 2.0) / 4.0, 0.0)


def clamp_toksvig(corners: np.ndarray, n: np.ndarray, **_options) -> np.ndarray:
    """Toksvig 2005: s' = s / (1 + s sigma^2), sigma^2 = (1 - |Na|) / |Na|, s = 4 n."""
    length = np.linalg.norm(corners.mean(axis=1), axis=1)
    sigma2 = (1.0 - length) / np.maximum(length, 1e-12)
    s = 4.0 * np.asarray(n, dtype=np.float64)
    return s / (1.0 + s * sigma2) / 4.0


def clamp_vlachos(corners: np.ndarray, n: np.ndarray, **_options) -> np.ndarray:
    """Vlachos 2015: alpha' = max(alpha, max(|dn/dx|^2, |dn/dy|^2)^(1/3))."""
    dx, dy = normal_derivatives(corners)
    geometric = np.maximum(np.einsum("ij,ij->i", dx, dx), np.einsum("ij,ij->i", dy, dy)) ** (1.0 / 3.0)
    alpha = np.maximum(np.sqrt(exponent_to_alpha2(n)), np.minimum(geometric, 1.0))
    return alpha2_to_exponent(alpha**2)


def clamp_tokuyoshi(corners: np.ndarray, n: np.ndarray, **_options) -> np.ndarray:
    """Tokuyoshi & Kaplanyan 2021: alpha'^2 = sat(alpha^2 + min(k (|dn/dx|^2 + |dn/dy|^2), kappa))."""
    dx, dy = normal_derivatives(corners)
    variance = TOKUYOSHI_K * (np.einsum("ij,ij->i", dx, dx) + np.einsum("ij,ij->i", dy, dy))
    alpha2 = np.minimum(exponent_to_alpha2(n) + np.minimum(variance, TOKUYOSHI_KAPPA), 1.0)
    return alpha2_to_exponent(alpha2)


