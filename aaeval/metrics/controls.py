"""Controls with known answers for every temporal measure: what each scores on images whose
right answer is known by construction.

The truth is a thin vertical highlight (0.4 px wide, energy :data:`ENERGY` per row) drifting
0.15 px a frame, box-filtered exactly. Each control is built from it:

- ``truth``: the truth itself (every error measure: 0);
- ``steady_bias``: the truth at half its intensity in every frame (a bias of -50%, no flicker
  of the energy; per pixel the error moves with the highlight, so pixel flicker counts it);
- ``steady_offset``: the truth plus 0.1 on every pixel and frame (a pixel bias that stays put);
- ``popping``: the truth brightened and dimmed by 20% in alternate frames (flicker of 20%
  per frame, no bias on average);
- ``steady_gain``: the truth 20% brighter in every frame (the popping's RMS error, held
  still: a perceptual measure must find it less visible than the popping);
- ``steady_blur``: the truth blurred by a Gaussian of 1 px in every frame (wider, but
  steady: a flicker measure must score it 0).

:func:`control_scores` computes every registered temporal metric (or those named: a sweep
scores the ones it measured) on every control, so a new measure is scored without further work; :data:`EXPECTED` states the answers known by
construction, and :data:`WORSE` the pairs of controls a measure must rank one way
(the first worse than the second). ``tests/metrics/test_metric_controls.py`` holds every
measure to them, and the report's "how to read" prints the scores beside them.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["FRAMES", "HEIGHT", "WIDTH", "ENERGY", "CONTROLS", "CONTROL_NOTES", "EXPECTED", "WORSE", "controls",
           "control_scores"]

FRAMES, HEIGHT, WIDTH = 8, 6, 16
#: The highlight's energy per row: half the display's range, so that the controls 20 %
#: brighter are not clipped where a perceptual measure shows them on a display.
ENERGY = 0.5
#: Popping amount and steady bias of the controls (relative).
POP, DIM, OFFSET = 0.2, 0.5, 0.1

#: The controls, in the order the page shows them.
CONTROLS = ("truth", "steady_bias", "steady_offset", "popping", "steady_gain", "steady_blur")
CONTROL_NOTES = {
    "truth": "the truth itself",
    "steady_bias": f"the truth at {1 - DIM:.0%} intensity, every frame",
    "steady_offset": f"the truth plus {OFFSET:g} on every pixel, every frame",
    "popping": f"the truth {POP:.0%} brighter and dimmer in alternate frames",
    "steady_gain": f"the truth {POP:.0%} brighter, every frame (the popping's RMS error, steady)",
    "steady_blur": "the truth blurred by a 1 px Gaussian, every frame (steady)",
}

#: Answers known by construction, (measure, control) -> value; a measure absent here for a
#: control has no answer fixed by the construction (a pixel RMS depends on the profile).
EXPECTED: dict[tuple[str, str], float] = {
    **{(m, "truth"): 0.0 for m in ("sum_variation", "sum_bias", "temporal_bias", "flicker", "highlight_bias",
                                   "highlight_energy_flicker", "highlight_profile_flicker", "highlight_flicker")},
    ("sum_variation", "steady_bias"): 0.0,
    ("sum_variation", "popping"): 2 * POP,  # sums (1 + POP) S and (1 - POP) S: (max - min) / mean
    ("sum_bias", "steady_bias"): -DIM,
    ("sum_bias", "popping"): 0.0,  # median of +POP and -POP frames, as many of each
    ("flicker", "steady_offset"): 0.0,
    ("temporal_bias", "steady_offset"): OFFSET,
    ("sum_variation", "steady_offset"): 0.0,
    ("highlight_flicker", "steady_offset"): 0.0,
    # where the truth is constant, only the test's own change counts: none in these controls
    **{("image_flicker", c): 0.0 for c in ("truth", "steady_bias", "steady_offset", "popping")},
    ("highlight_bias", "steady_bias"): -DIM,
    ("highlight_bias", "popping"): 0.0,
    ("highlight_energy_flicker", "steady_bias"): 0.0,
    ("highlight_energy_flicker", "popping"): POP,
    ("highlight_profile_flicker", "steady_bias"): 0.0,
    ("highlight_profile_flicker", "popping"): POP,
    ("highlight_profile_flicker", "steady_blur"): 0.0,
    # a steady gain is bias alone
    **{(m, "steady_gain"): 0.0 for m in ("sum_variation", "image_flicker", "highlight_energy_flicker",
                                        "highlight_profile_flicker")},
    ("sum_bias", "steady_gain"): POP,
    ("highlight_bias", "steady_gain"): POP,
    ("cvvdp", "truth"): 10.0,  # JOD of a test no one can tell from the reference
}

#: (measure, worse control, better control): orders known by construction without a value.
WORSE: tuple[tuple[str, str, str], ...] = (
    ("cvvdp", "popping", "steady_gain"),  # the same RMS error, popping is the more visible
)


def _truth() -> np.ndarray:
    cols = np.arange(WIDTH)
    out = np.zeros((FRAMES, HEIGHT, WIDTH))
    for t in range(FRAMES):  # FRAMES columns of coverage: no per-pixel loop
        left = 7.3 + 0.15 * t
        right = left + 0.4
        out[t] = (np.clip(np.minimum(right, cols + 1) - np.maximum(left, cols), 0, None) / 0.4)[None, :]
    return out


def controls() -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The truth (F, H, W, 3), each control by name (same shape) and the masks by name
    (F, H, W): ``highlight`` (the truth's highlight pixels) and ``interior`` (the pixels
    where the truth does not change: a region whose ideal image is constant)."""
    from scipy import ndimage

    from aaeval.metrics.specular import highlight_mask

    truth = ENERGY * _truth()
    alternate = np.where(np.arange(FRAMES) % 2 == 0, 1.0, -1.0)[:, None, None]
    gray = {
        "truth": truth,
        "steady_bias": truth * (1.0 - DIM),
        "steady_offset": truth + OFFSET,
        "popping": truth * (1.0 + POP * alternate),
        "steady_gain": truth * (1.0 + POP),
        "steady_blur": np.stack([ndimage.gaussian_filter(f, sigma=1.0, mode="nearest") for f in truth]),
    }
    masks = {"highlight": np.stack([highlight_mask(f) for f in truth]),
             "interior": np.broadcast_to(np.ptp(truth, axis=0) == 0.0, truth.shape)}

    def rgb(frames):
        return np.repeat(frames[..., None], 3, axis=-1)

    return rgb(truth), {name: rgb(gray[name]) for name in CONTROLS}, masks


def control_scores(names=None) -> list[dict]:
    """Every registered temporal metric (those of ``names`` when given) on every control:
    rows of ``measure``, ``title``, ``control``, ``score`` (NaN where the measure raised),
    ``expected`` (NaN where the construction fixes no answer)."""
    from aaeval.metrics.registry import METRICS, compute_temporal_metric

    truth, tests, masks = controls()
    rows = []
    for name, metric in METRICS.items():
        if metric.kind != "temporal" or metric.unavailable() or (names is not None and name not in names):
            continue
        context = {}
        if metric.mask:
            context["mask"] = masks.get(metric.mask, masks["highlight"])
        if "exact" in metric.needs:
            context["exact"] = truth  # the truth here is exact (a box-filtered coverage)
        for control in CONTROLS:
            try:
                score = compute_temporal_metric(name, truth, tests[control], **context)
            except (ValueError, TypeError):
                score = math.nan
            rows.append({"measure": name, "title": metric.title, "control": control, "score": float(score),
                         "expected": EXPECTED.get((name, control), math.nan)})
    return rows
