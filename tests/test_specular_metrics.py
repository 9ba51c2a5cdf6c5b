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
    steady = true - 0.1
    assert highlight_flicker(true, steady, mask=mask) == pytest.approx(0.0, abs=1e-12)
    noisy = true + 0.1 * np.where(np.arange(6)[:, None, None] % 2 == 0, 1.0, -1.0)
    assert highlight_flicker(true, noisy, mask=mask) == pytest.approx(0.1)
    assert highlight_energy_flicker(true, true * 0.5, mask=mask) == pytest.approx(0.0, abs=1e-12)
    assert highlight_energy_flicker(true, noisy, mask=mask) > 0


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
