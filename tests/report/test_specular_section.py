"""The specular section reads the tables: one ground truth, bias and flicker side by side."""

from __future__ import annotations

import re

import pandas as pd
import pytest

from aaeval.metrics import METRICS
from aaeval.report.specular_section import BIAS, ERROR, FLICKER, specular_section
from aaeval.report.style import Styles
from tests.helpers.findings_util import findings_report


def test_no_section_for_a_sweep_without_shaded_scenes(tmp_path):
    from aaeval.report.sweep_data import SweepData

    results = pd.DataFrame({"group": ["a"], "scene_digest": ["d"], "method": ["catmull"], "options": ["{}"],
                            "shaded": [False]})
    styles = Styles([("catmull", {})])
    data = SweepData(None, {}, results, pd.DataFrame(), pd.DataFrame())
    assert specular_section(tmp_path, tmp_path / "figures", data, styles=styles) == ""
    assert not (tmp_path / "figures").exists()


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return findings_report(tmp_path_factory)


# on the worker that builds the findings report for tests/report/test_report_findings.py (pyproject's
# --dist loadgroup): on another worker this test would build it again (20-25 s)
@pytest.mark.xdist_group("report_findings")
def test_section_states_one_ground_truth_and_ranks_by_flicker(out):
    from aaeval.sweeps.table import read_table

    text = (out / "index.html").read_text()
    section = text[text.index("<h2 id='specular'>"):text.index("<h2 id='filters'>")]
    assert section.count(" spp, seed ") == 1  # the truth's spp stated once
    assert "mitsuba:seed=0,spp=64" in section or "mitsuba:spp=64" in section
    results, temporal = read_table(out / "results.parquet"), read_table(out / "temporal.parquet")
    table = pd.read_parquet(out / "summaries" / "specular.parquet")
    table = table[table["group"] == "specular"]
    flicker = table["highlight_profile_flicker"].to_list()
    assert flicker == sorted(flicker) and len(flicker) == 3
    shown = re.findall(r"<tr><td[^>]*>([^<]+)</td>", section[section.index("<table class='specular'"):])
    assert shown[:3] == table["label"].to_list()
    # every number of the section is the tables' own: per spec, the mean over the group's
    # finished cells (results.parquet) or animations (temporal.parquet), shown in the metric's format
    cells = results[(results["group"] == "specular") & results["error"].isna()]
    series = temporal[temporal["group"] == "specular"]
    rows = re.findall(r"<tr><td[^>]*>([^<]+)</td><td class='num'[^>]*>([^<]+)</td><td class='num'[^>]*>([^<]+)</td>"
                      r"<td class='num'[^>]*>([^<]+)</td>", section[section.index("<table class='specular'"):])
    assert len(rows) == 3
    for (label, error, bias, flick), spec in zip(rows, table["spec"]):
        expected = {ERROR: cells.loc[cells["spec"] == spec, ERROR].mean(),
                    BIAS: series.loc[series["spec"] == spec, BIAS].mean(),
                    FLICKER: series.loc[series["spec"] == spec, FLICKER].mean()}
        row = table[table["spec"] == spec].iloc[0]
        for name, value in expected.items():
            assert row[name] == pytest.approx(value, rel=1e-12), (spec, name)
        assert (error, bias, flick) == tuple(METRICS[n].format(expected[n]) for n in (ERROR, BIAS, FLICKER)), spec
    for src in re.findall(r"<img src='([^']+)'", section):
        assert (out / src).stat().st_size > 1000
