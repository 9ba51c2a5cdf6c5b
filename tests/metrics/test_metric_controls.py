"""Controls with known answers for the temporal and highlight measures.

A thin vertical highlight (0.4 px wide, unit energy per row) drifts 0.15 px a frame and is
box-filtered exactly: the truth. Each control is built from it with a known answer.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from aaeval.metrics import registry
from aaeval.metrics.specular import highlight_mask

FRAMES, HEIGHT, WIDTH = 8, 6, 16


def _truth():
    cols = np.arange(WIDTH)
    out = np.zeros((FRAMES, HEIGHT, WIDTH))
    for t in range(FRAMES):
        left = 7.3 + 0.15 * t
        right = left + 0.4
        out[t] = (np.clip(np.minimum(right, cols + 1) - np.maximum(left, cols), 0, None) / 0.4)[None, :]
    return out


def _alternating(amount):
    return amount * np.where(np.arange(FRAMES) % 2 == 0, 1.0, -1.0)[:, None, None]


TRUTH = _truth()
MASK = np.stack([highlight_mask(f) for f in TRUTH])
STEADY_BLUR = np.stack([ndimage.gaussian_filter(f, sigma=1.0, mode="nearest") for f in TRUTH])
CONTROLS = {
    "truth": TRUTH,
    "steady_bias": TRUTH * 0.5,
    "popping": TRUTH * (1.0 + _alternating(0.2)),
    "steady_blur": STEADY_BLUR,
}


def score(name, test):
    return registry.compute_temporal_metric(name, TRUTH, test, mask=MASK)


@pytest.mark.parametrize("name", ["highlight_profile_flicker", "highlight_energy_flicker"])
def test_highlight_flicker_controls(name):
    assert score(name, CONTROLS["truth"]) == pytest.approx(0.0, abs=1e-12)
    assert score(name, CONTROLS["steady_bias"]) == pytest.approx(0.0, abs=1e-12)
    assert score(name, CONTROLS["popping"]) == pytest.approx(0.2, rel=1e-9)


def test_steady_blur_is_steady_on_the_cross_section_measure():
    assert abs(score("highlight_profile_flicker", STEADY_BLUR)) < 1e-6


def test_whole_image_energy_ratio_fails_the_steady_blur_control():
    # Blur pushes energy outside the per-frame mask by an amount that depends on the
    # highlight's sub-pixel phase: the energy ratio calls a steady image flicker.
    assert score("highlight_energy_flicker", STEADY_BLUR) > 1e-3


def test_highlight_bias_controls():
    assert score("highlight_bias", CONTROLS["truth"]) == pytest.approx(0.0, abs=1e-12)
    assert score("highlight_bias", CONTROLS["steady_bias"]) == pytest.approx(-0.5)
    assert score("highlight_bias", CONTROLS["popping"]) == pytest.approx(0.0, abs=1e-12)


def rgb(frames):
    return np.repeat(frames[..., None], 3, axis=-1)


def test_pixel_flicker_and_bias_controls():
    def both(test):
        return (registry.compute_temporal_metric("flicker", rgb(TRUTH), rgb(test)),
                registry.compute_temporal_metric("temporal_bias", rgb(TRUTH), rgb(test)))

    assert both(TRUTH) == pytest.approx((0.0, 0.0), abs=1e-12)
    assert both(TRUTH + 0.1) == pytest.approx((0.0, 0.1), abs=1e-12)
    assert both(TRUTH + _alternating(0.1)) == pytest.approx((0.1, 0.0), abs=1e-12)


def test_highlight_change_error_controls():
    assert score("highlight_flicker", TRUTH) == pytest.approx(0.0, abs=1e-12)
    assert score("highlight_flicker", TRUTH - 0.1) == pytest.approx(0.0, abs=1e-12)
    jump = TRUTH + _alternating(0.1)
    assert score("highlight_flicker", jump) == pytest.approx(0.2, rel=1e-9)


def test_sum_variation_controls():
    truth = rgb(TRUTH)
    steady = np.broadcast_to(truth[0], truth.shape)
    assert registry.compute_temporal_metric("sum_variation", truth, steady) == pytest.approx(0.0, abs=1e-12)
    assert registry.compute_temporal_metric("sum_variation", truth, truth) == pytest.approx(0.0, abs=1e-12)
    # sums 1.1 S and 0.9 S: (max - min) / mean = 0.2
    popping = rgb(TRUTH * (1.0 + _alternating(0.1)))
    assert registry.compute_temporal_metric("sum_variation", truth, popping) == pytest.approx(0.2, rel=1e-9)


# --- the library's controls (aaeval.metrics.controls), the ones the report prints ---------

def test_sum_bias_controls():
    truth = rgb(TRUTH)
    exact = {"exact": truth}
    assert registry.compute_temporal_metric("sum_bias", truth, truth, **exact) == pytest.approx(0.0, abs=1e-12)
    steady = np.broadcast_to(truth[0], truth.shape)  # steady: every frame's sum is the exact one
    assert registry.compute_temporal_metric("sum_bias", truth, steady, **exact) == pytest.approx(0.0, abs=1e-12)
    assert registry.compute_temporal_metric("sum_bias", truth, truth * 0.83, **exact) == pytest.approx(-0.17)
    # five frames in six 10% dark, one 50% bright: the typical frame is 10% dark
    scale = np.where(np.arange(FRAMES) % 6 == 5, 1.5, 0.9)[:, None, None, None]
    assert registry.compute_temporal_metric("sum_bias", truth, truth * scale, **exact) == pytest.approx(-0.1)


def test_sum_bias_reads_the_exact_frames_not_the_reference():
    truth = rgb(TRUTH)
    noisy_reference = truth * 1.3  # a reference whose sum is off must not move the bias
    assert registry.compute_temporal_metric("sum_bias", noisy_reference, truth, exact=truth) == \
        pytest.approx(0.0, abs=1e-12)


def test_every_temporal_measure_meets_the_known_answers_of_the_controls():
    from aaeval.metrics.controls import WORSE, control_scores

    rows = control_scores()
    checked = [r for r in rows if np.isfinite(r["expected"])]
    missed = [(r["measure"], r["control"], r["score"], r["expected"]) for r in checked
              if not abs(r["score"] - r["expected"]) <= 1e-9]
    assert not missed
    score = {(r["measure"], r["control"]): r["score"] for r in rows}
    ordered = [(m, worse, better) for m, worse, better in WORSE if (m, worse) in score]
    for m, worse, better in ordered:
        sign = 1.0 if registry.METRICS[m].higher_is_better else -1.0
        assert sign * score[m, worse] < sign * score[m, better], (m, worse, better)
    # every temporal measure available here is held to at least two known answers or orders
    temporal = [n for n, m in registry.METRICS.items() if m.kind == "temporal" and not m.unavailable()]
    counts = {n: sum(r["measure"] == n for r in checked) + sum(o[0] == n for o in ordered) for n in temporal}
    assert all(c >= 2 for c in counts.values()), counts


def test_library_controls_match_this_file():
    # the page's controls are the ones this file builds by hand
    from aaeval.metrics.controls import ENERGY, controls

    truth, tests, masks = controls()
    assert np.array_equal(truth[..., 0], ENERGY * TRUTH)
    assert np.allclose(tests["steady_blur"][..., 0], ENERGY * STEADY_BLUR, rtol=0, atol=1e-15)
    assert np.array_equal(masks["highlight"], MASK)


def test_the_report_prints_every_measures_control_scores():
    import re

    from aaeval.sweeps.report_files import controls_of
    from aaeval.metrics.controls import control_scores
    from aaeval.report.controls_table import controls_html

    page = controls_html(controls_of())  # what the sweep stores in controls.json
    for r in control_scores():
        cell = re.search(rf"data-measure='{r['measure']}' data-control='{r['control']}'>(.*?)</td>", page)
        assert cell, (r["measure"], r["control"])
        shown = re.sub(r"<[^>]+>", "", cell.group(1))
        metric = registry.METRICS[r["measure"]]
        assert shown.startswith(metric.format(r["score"]) if np.isfinite(r["score"]) else "n/a")
    assert "✗" not in page  # no measure misses a known answer
    assert len(CONTROLS) >= 4
