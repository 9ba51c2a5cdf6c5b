"""Highlight metrics on hand-made images whose answers are known."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.metrics.specular import (
    detection_precision_recall,
    highlight_energy_bias,
    highlight_energy_flicker,
    highlight_flicker,
    highlight_mask,
    highlight_profile_flicker,
    highlight_rmse,
)


def test_rmse_and_bias_only_see_the_mask():
    true = np.zeros((4, 5))
    true[1, 1:4] = [0.5, 1.0, 0.5]
    test = true * 0.5
    test[3, 4] = 9.0  # outside the highlight: ignored
    mask = highlight_mask(true, threshold=0.1)
    assert mask.sum() == 3
    assert highlight_energy_bias(true, test, mask=mask) == pytest.approx(-0.5)
    assert highlight_rmse(true, test, mask=mask) == pytest.approx(np.sqrt((0.25**2 * 2 + 0.5**2) / 3))


def test_flicker_ignores_steady_bias_but_sees_breakup():
    rng = np.random.default_rng(1)
    true = rng.random((6, 8, 8))
    mask = np.ones((8, 8), bool)
    assert highlight_flicker(true, true - 0.1, mask=mask) == pytest.approx(0.0, abs=1e-12)
    popping = true + 0.1 * np.where(np.arange(6)[:, None, None] % 2 == 0, 1.0, -1.0)
    assert highlight_flicker(true, popping, mask=mask) == pytest.approx(0.2)
    # a frozen image while the truth moves also departs from the truth's change
    frozen = np.broadcast_to(true[0], true.shape)
    assert highlight_flicker(true, frozen, mask=mask) == pytest.approx(np.sqrt(np.mean(np.diff(true, axis=0) ** 2)))
    assert highlight_energy_flicker(true, true * 0.5, mask=mask) == pytest.approx(0.0, abs=1e-12)
    assert highlight_energy_flicker(true, popping, mask=mask) > 0


def drifting_line(frames, width, sampler):
    """A 0.4-px-wide vertical line of unit energy per row, drifting 0.15 px per frame."""
    out = np.zeros((frames, 5, width))
    for t in range(frames):
        left = 3.3 + 0.15 * t
        out[t] = sampler(left, left + 0.4, np.arange(width))[None, :]
    return out


def test_profile_flicker_separates_area_from_point_sampling():
    def area(a, b, cols):  # exact box filter: overlap of [a, b] with each pixel, / width
        return np.clip(np.minimum(b, cols + 1) - np.maximum(a, cols), 0, None) / (b - a)

    def point(a, b, cols):  # pixel-centre sampling of the same line
        return ((cols + 0.5 >= a) & (cols + 0.5 < b)) / (b - a)

    truth = drifting_line(8, 10, area)
    mask = np.ones((5, 10), bool)
    assert highlight_profile_flicker(truth, truth * 0.8, mask=mask) == pytest.approx(0.0, abs=1e-12)
    sampled = drifting_line(8, 10, point)
    assert highlight_profile_flicker(truth, sampled, mask=mask) > 0.5


def test_precision_recall():
    true = np.zeros((2, 3))
    test = np.array([[0.5, 0.0, 0.5], [0.0, 0.0, 0.01]])
    flagged = np.array([[True, True, False], [False, False, False]])
    assert detection_precision_recall(true, test, flagged=flagged, tolerance=0.02) == (0.5, 0.5)


def test_shape_mismatch_is_refused():
    with pytest.raises(ValueError, match="shape"):
        highlight_rmse(np.zeros((2, 2)), np.zeros((2, 3)), mask=np.ones((2, 2), bool))
    with pytest.raises(ValueError, match="2 frames"):
        highlight_flicker(np.zeros((1, 2, 2)), np.zeros((1, 2, 2)), mask=np.ones((2, 2), bool))
