"""The truth's noise on each metric's own pixels, and the z-test that decides
agreement and ties (aaeval/metrics/agreement.py)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from aaeval.metrics.agreement import (PASS_FRACTION, agrees, noise_strata, sidak_threshold,
                                      z_test_pass_fraction)


def test_sidak_threshold_holds_the_family_to_its_level():
    for n in (1, 10, 1000):
        z = sidak_threshold(n, 0.01)
        per_pixel = 2 * stats.norm.sf(z)  # two-sided
        assert 1 - (1 - per_pixel) ** n == pytest.approx(0.01, rel=1e-9)
    assert sidak_threshold(1, 0.01) == pytest.approx(2.5758293035489, rel=1e-12)


def _noisy(shape, sigma, rng):
    return rng.normal(0.0, sigma, shape)


def test_noise_strata_are_measured_on_each_kind_of_pixel():
    rng = np.random.default_rng(0)
    edge = np.zeros((40, 40), bool)
    edge[:, 18:22] = True
    sigma = np.where(edge, 0.01, 0.0)[..., None]  # only edge pixels are noisy (flat ones are exact)
    truth = 0.5 + sigma * rng.standard_normal((40, 40, 3))
    twin = 0.5 + sigma * rng.standard_normal((40, 40, 3))
    everything, on_edges, elsewhere = noise_strata(truth, twin, np.ones_like(edge), edge)
    assert on_edges == pytest.approx(0.01, rel=0.1)
    assert elsewhere == 0.0
    assert everything == pytest.approx(0.01 * math.sqrt(edge.mean()), rel=0.1)  # diluted by flat pixels
    # over the edge mask alone the noise is the edge pixels'
    assert noise_strata(truth, twin, edge, edge)[0] == pytest.approx(on_edges)


def test_a_render_with_the_truths_noise_agrees_and_a_biased_one_does_not():
    rng = np.random.default_rng(1)
    edge = np.zeros((64, 64), bool)
    edge[10:54, 30:34] = True
    mask = np.ones_like(edge)
    sigma_edge = 0.01
    mean = np.full((64, 64, 3), 0.3)
    truth = mean + np.where(edge[..., None], sigma_edge, 0.0) * rng.standard_normal(mean.shape)
    exact = mean  # an exact method: its only difference from the truth is the truth's own noise
    fraction = z_test_pass_fraction(truth, exact, mask, edge, sigma_edge, 0.0)
    assert agrees(fraction) and fraction >= PASS_FRACTION
    off = mean + np.where(edge[..., None], 0.06, 0.0)  # 6 sigma too bright on the edges
    assert not agrees(z_test_pass_fraction(truth, off, mask, edge, sigma_edge, 0.0))
    # where the truth is exact (flat pixels), any difference above rounding fails
    flat_off = mean + np.where(edge[..., None], 0.0, 1e-4)
    assert not agrees(z_test_pass_fraction(truth, flat_off, mask, edge, sigma_edge, 0.0))
    assert math.isnan(z_test_pass_fraction(truth, exact, np.zeros_like(edge), edge, sigma_edge, 0.0))
    assert agrees(math.nan) is None


def test_ties_in_the_findings_follow_the_test_not_the_gap():
    from aaeval.report.findings import QUESTIONS, leader_sentence

    edges = next(q for q in QUESTIONS if q.key == "edges")
    table = pd.DataFrame({"spec": ["a", "b"], "label": ["a", "b"], "method": ["a", "b"], "options": ["{}", "{}"], "ladder": ["a|{}", "b|{}"],
                          "value": [1.0e-3, 1.4e-3], "noise": [1.0e-3, 1.0e-3], "rows": [4, 4],
                          "agreement": [0.9990, 0.9980]})
    assert " tie (" in leader_sentence(edges, table, "g")  # both pass the z-test
    table.loc[1, "agreement"] = 0.90  # b fails it: the gap, under the noise, is resolved by the test
    assert "leads with" in leader_sentence(edges, table, "g")


def test_per_scene_table_shows_each_animation():
    from aaeval.sweeps.summaries import QUESTIONS, per_scene_values
    from aaeval.metrics import METRICS
    from aaeval.report.findings import per_scene_html
    from aaeval.report.sweep_data import METRICS as SHOWN

    sums = next(q for q in QUESTIONS if q.key == "sums")
    frame = pd.DataFrame({"group": ["g"] * 4, "scene": ["f1", "f2", "f1", "f2"], "spec": ["s", "s", "t", "t"],
                          "label": ["s", "s", "t", "t"], "sum_variation": [0.5, 0.1, 0.0, 0.0],
                          "sum_bias": [-1 / 6, -0.01, 0.0, 0.0]})
    infos = {name: m.info() for name, m in METRICS.items()}
    stored = per_scene_values(sums, frame, "g", ["s", "t"])
    SHOWN.update(infos)
    page = per_scene_html(sums, stored)
    at = stored[(stored["spec"] == "s") & (stored["scene"] == "f1") & (stored["column"] == "sum_bias")].index[0]
    assert f"data-row='{at}' data-column='value' data-fmt='{infos['sum_bias'].fmt}'>-16.67%<" in page
    at = stored[(stored["spec"] == "s") & (stored["scene"] == "f2") & (stored["column"] == "sum_variation")].index[0]
    assert f"data-row='{at}' data-column='value' data-fmt='{infos['sum_variation'].fmt}'>1.000e-01<" in page
    assert per_scene_html(sums, stored[stored["scene"] == "f1"]) == ""


def test_noise_weight_is_the_colour_range_of_the_fragments_meeting_in_a_pixel():
    from aaeval.metrics.edges import noise_weight
    from aaeval.scenes import parse_scene

    scene = parse_scene({"image": {"width": 4, "height": 2, "background": [0.0, 0.0, 0.0]},
                         "polygons": [{"color": [0.8, 0.3, 0.0], "vertices": [[1.5, 0, 0], [4, 0, 0], [4, 2, 0],
                                                                                [1.5, 2, 0]]}]})
    weight = noise_weight(scene)
    assert np.allclose(weight[:, 1], [0.8, 0.3, 0.0])  # the edge's pixel: polygon against black
    assert np.allclose(weight[:, [0, 2, 3]], 0.0)  # one colour: exact whatever the sampler


def test_the_colour_weight_keeps_an_exact_method_agreeing_at_a_high_contrast_channel():
    # half the edge pixels are one bright green edge, half a faint grey one: coverage noise
    # scales with each channel's contrast, so one sigma for every value is 2.4x too small
    # on the green channel of the bright edge
    rng = np.random.default_rng(2)
    edge = np.zeros((64, 64), bool)
    edge[:, 16:48] = True
    weight = np.zeros((64, 64, 3))
    weight[:32][edge[:32]] = [0.0, 1.0, 0.0]
    weight[32:][edge[32:]] = [0.05, 0.05, 0.05]
    mean = np.full((64, 64, 3), 0.2)
    truth = mean + 0.004 * rng.standard_normal((64, 64, 1)) * weight
    twin = mean + 0.004 * rng.standard_normal((64, 64, 1)) * weight
    _, pooled, other = noise_strata(truth, twin, edge, edge)  # no weight: one sigma for every value
    _, scale, _ = noise_strata(truth, twin, edge, edge, weight)
    assert scale == pytest.approx(0.004, rel=0.1)
    with_weight = z_test_pass_fraction(truth, mean, edge, edge, scale, other, weight=weight)
    without = z_test_pass_fraction(truth, mean, edge, edge, pooled, other)
    assert agrees(with_weight) and not agrees(without)


def test_a_seeded_method_is_tested_within_its_own_noise_against_an_exact_truth():
    # an exact reference has no noise (no stratum above 0); a Monte Carlo render (unbiased)
    # then differs by its sampling noise on every edge pixel, and the question the z-test
    # answers is whether it agrees within that noise (its own, from the next seed); a
    # deterministic method that is off (point sampling) has no noise of its own and differs
    from aaeval.sweeps.measure import measure_frame, render_reference
    from aaeval.renderers import MethodSpec
    from aaeval.scenes import parse_scene
    from aaeval.scenes.generate import generate_scene

    scene = parse_scene(generate_scene("edges", 0.2, size=24))
    truth = render_reference(scene, MethodSpec.parse("catmull"), 0, estimate_noise=True)
    assert not any(v > 0 for strata in truth["noise_by_metric"].values() for v in strata)

    def passing(spec):
        m = measure_frame(scene, MethodSpec.parse(spec), 0, truth["image"], ["rmse"], digest="own-noise",
                          noise_by_metric=truth["noise_by_metric"])
        assert m.error is None, m.error
        return m.agreement["rmse"]

    assert passing("mitsuba:sampler=stratified,spp=256,seed=2") >= PASS_FRACTION
    assert passing("point") < 0.9
