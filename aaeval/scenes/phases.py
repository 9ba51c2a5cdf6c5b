"""Sub-pixel phases of an animation that do not alias with sample grids.

A scene that moves by a fixed step commensurate with a regular sample grid (1/16 px over a
4 x 4 grid) meets that grid at a handful of phases only: a regular sampler can then show a
constant intensity sum while being 17% off in every frame (FIELD_NOTES, "Measuring
highlights and invariance"). Offsets drawn from a low-discrepancy sequence, or at random,
visit every sub-pixel phase evenly instead.

``[animation] phases`` (scene files) and an experiment's ``animate = {phases = ...}`` name
one of :data:`PHASES`; frame k is then moved by ``k * translate + phase_offsets(...)[k]``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PHASES", "R2_STEP", "phase_offset", "phase_offsets", "subpixel_phase"]

#: The plastic number g (g**3 = g + 1): the R2 sequence steps by (1/g, 1/g**2) modulo 1
#: (Roberts 2018), the two-dimensional analogue of golden-ratio steps; its points fill the
#: unit square with the lowest known discrepancy of any additive recurrence.
_PLASTIC = 1.32471795724474602596
R2_STEP = np.array([1.0 / _PLASTIC, 1.0 / _PLASTIC**2])

#: The phase sequences a scene may declare: ``none`` (no offsets, the default: a file
#: without ``phases`` moves exactly as it always did), ``r2`` and ``random`` (seeded).
PHASES = ("none", "r2", "random")


def phase_offsets(kind: str, frames: int, seed: int = 0) -> np.ndarray:
    """Sub-pixel offsets of every frame, shape (frames, 2), each in [0, 1) px, frame 0 at 0.

    Parameters
    ----------
    kind : {"none", "r2", "random"}
        ``none``: all zero. ``r2``: frame k at ``frac(k * R2_STEP)``. ``random``: uniform in
        [0, 1)**2 from ``numpy.random.default_rng(seed)``, frame 0 kept at 0.
    frames : int
        Number of frames (>= 1).
    seed : int
        Seed of ``random``; unused by the others.

    Returns
    -------
    offsets : ndarray, shape (frames, 2)
        Frame 0 is always (0, 0), so frame 0 of a scene is the scene as written.
    """
    if kind not in PHASES:
        raise ValueError(f"unknown phases {kind!r}; choices: {', '.join(PHASES)}")
    k = np.arange(int(frames), dtype=np.float64)[:, None]
    if kind == "none":
        return np.zeros((int(frames), 2))
    if kind == "r2":
        return np.mod(k * R2_STEP, 1.0)
    offsets = np.random.default_rng(int(seed)).random((int(frames), 2))
    offsets[0] = 0.0
    return offsets


def phase_offset(kind: str, frame: int, seed: int = 0) -> np.ndarray:
    """The sub-pixel offset of frame ``frame`` alone, shape (2,): ``phase_offsets(kind,
    frame + 1, seed)[frame]``, in constant time and memory whatever the frame.

    ``random`` draws two doubles per frame from ``numpy.random.default_rng(seed)`` (a
    PCG64), one 64-bit step each, so frame k's pair is the stream advanced by 2k steps
    (``PCG64.advance``): the same numbers as drawing every earlier frame's first.
    """
    if kind not in PHASES:
        raise ValueError(f"unknown phases {kind!r}; choices: {', '.join(PHASES)}")
    k = int(frame)
    if kind == "none" or k == 0:
        return np.zeros(2)
    if kind == "r2":
        return np.mod(k * R2_STEP, 1.0)
    stream = np.random.PCG64(int(seed))
    stream.advance(2 * k)
    return np.random.Generator(stream).random(2)


def subpixel_phase(offset) -> np.ndarray:
    """The sub-pixel phase of an offset (px): its fractional part in [0, 1), per axis."""
    return np.mod(np.asarray(offset, dtype=np.float64), 1.0)
