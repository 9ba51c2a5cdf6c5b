"""The filter experiment's measures (aaeval/report/filters_section.py) against closed forms.

- the 10-90% edge width measured on exact renders of the ``edges`` scene equals the width
  of the filter's own step response, found here by quadrature of Mitsuba's formulas;
- the picket fence of period one pixel does not flicker at all through a filter whose
  integer shifts sum to one, and does through the Gaussian;
- the section runs on a small sweep and writes its chart.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.scenes.generate import generate_scene
from aaeval.filters import FILTERS
from aaeval.renderers import render
from aaeval.sweeps.measure import scene_mask
from aaeval.metrics import image_flicker
from aaeval.metrics.filters import edges_window as _edge_window, edge_width_10_90
from aaeval.report.filters_section import filters_section
from aaeval.scenes import load_scene, parse_scene
from tests.helpers.filter_oracle import PROFILES

ROOT = Path(__file__).resolve().parents[2]


def step_response_width(name):
    """10-90% width of the normalised step response of the filter's profile."""
    _, k = PROFILES[name]
    knots = np.arange(-2.5, 2.51, 0.5)
    total = sum(quad(lambda t: float(k(t)), a, b)[0] for a, b in zip(knots[:-1], knots[1:]))

    def cdf(d):
        return quad(lambda t: float(k(t)), -2.5, d, points=[x for x in knots if -2.5 < x < d], limit=200)[0] / total

    return brentq(lambda d: cdf(d) - 0.9, -2.4, 2.4) - brentq(lambda d: cdf(d) - 0.1, -2.4, 2.4)


@pytest.mark.parametrize("name", list(FILTERS))
def test_edge_width_matches_the_filters_step_response(name):
    scene = parse_scene(generate_scene("edges", 0.05, size=48, frames=8))
    frames = np.stack([render(scene, f"catmull:filter={name}", frame=k) for k in range(scene.frames)])
    rows, cols = _edge_window(48, 48)
    tolerance = 5e-3 if name == "gaussian" else 1e-3  # the Gaussian's rows align only nearly
    assert abs(edge_width_10_90(frames, rows=rows, cols=cols) - step_response_width(name)) < tolerance


def test_period_one_fence_flickers_only_through_the_gaussian():
    scene = load_scene(ROOT / "configs" / "scenes" / "picket_fence.toml")
    mask = np.stack([scene_mask("interior", scene.at_frame(k)) for k in range(scene.frames)])
    assert mask.all(axis=0).sum() >= 20
    for name, filt in FILTERS.items():
        frames = np.stack([render(scene, f"catmull:filter={name}", frame=k) for k in range(scene.frames)])
        value = image_flicker(frames, frames, mask=mask)
        assert (value < 1e-12) if filt.partition_of_unity else (value > 1e-4), (name, value)


@pytest.mark.slow
@pytest.mark.xdist_group("report_findings")  # the worker that builds the findings report once
def test_section_reads_the_tables_and_judges_each_filter_by_its_own_truth(tmp_path_factory):
    from tests.helpers.findings_util import findings_report

    out = findings_report(tmp_path_factory)
    text = (out / "index.html").read_text()
    section = text[text.index("<h2 id='filters'>"):]
    assert "judged against the ground truth through its own filter" in section
    for word in ("tent", "box", "supersample:k=2", "image flicker (interior)"):
        assert word in section
    assert (out / "tables" / "filters_filters.csv").is_file()
    assert filters_section(out, out / "figures") != ""  # reads results.parquet itself when not given
    # the numbers of the section's table are the sweep tables' own: per spec, the mean over
    # the group's finished cells (results.parquet) or animations (temporal.parquet)
    table = pd.read_csv(out / "tables" / "filters_filters.csv")
    results, temporal = pd.read_parquet(out / "results.parquet"), pd.read_parquet(out / "temporal.parquet")
    for frame, column, title in ((results, "rmse", "RMSE"), (temporal, "image_flicker", "image flicker (interior)")):
        rows = frame[(frame["group"] == "filters") & frame["error"].isna()] if "error" in frame else \
            frame[frame["group"] == "filters"]
        expected = sorted(rows.groupby("spec")[column].mean().dropna())
        shown = sorted(table[title].dropna())
        assert len(shown) == len(table) == len(expected) > 0, (column, shown, expected)
        assert shown == pytest.approx(expected, rel=1e-12), column
