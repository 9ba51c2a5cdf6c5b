"""The HTML report: every link resolves, every comparison names its ground truth, exact methods
are checked against it, figures and tables come in paper formats."""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from urllib.parse import unquote, urlparse

import numpy as np
import pandas as pd
import pytest

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.sweeps.store import SweepStore
from aaeval.sweeps.report_files import write_sweep_files
from aaeval.report import write_report
from aaeval.report.names import figure_stem
from aaeval.report.figures import pareto_front
from tests.helpers.report_util import small_report
from tests.helpers.sweep_util import write_config


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.ids, self.figcaptions, self._in_caption = [], set(), [], False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        for key in ("src", "href"):
            if attrs.get(key):
                self.links.append((tag, attrs[key]))
        if tag == "figcaption":
            self._in_caption = True
            self.figcaptions.append("")

    def handle_endtag(self, tag):
        if tag == "figcaption":
            self._in_caption = False

    def handle_data(self, data):
        if self._in_caption:
            self.figcaptions[-1] += data


# one worker builds the small report for this module and test_report_browser.py (pyproject's
# --dist loadgroup), instead of each worker building its own (about 30 s each)
# slow: a sweep and its report built first (about 7 s)
pytestmark = [pytest.mark.xdist_group("small_report"), pytest.mark.slow]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    return small_report(tmp_path_factory)


def test_every_link_resolves(report):
    parser = _Links()
    parser.feed(report.read_text())
    imgs = [link for tag, link in parser.links if tag == "img"]
    assert len(imgs) >= 8  # accuracy x3, validation, error per frame, intensity sum, flicker, space-time, ...
    for tag, link in parser.links:
        url = urlparse(link)
        assert not url.scheme and not url.netloc, f"report must be self-contained: {link}"
        if link.startswith("#"):
            assert link[1:] in parser.ids, link
            continue
        target = report.parent / unquote(url.path)
        assert target.is_file() and target.stat().st_size > 0, f"{tag} {link} does not resolve"


def test_every_group_figure_states_its_ground_truth(report):
    parser = _Links()
    parser.feed(report.read_text())
    captions = [c for c in parser.figcaptions if "validation" not in c and "over that ground truth" not in c]
    assert captions
    for caption in captions:
        assert ("Reference: mitsuba:sampler=stratified,spp=256 (Mitsuba ground truth; stochastic; spp 256, "
                "seed 0; measured noise RMS" in caption
                or "Reference: catmull (NOT the Mitsuba ground truth; exact; noise 0)" in caption), caption


def test_catmull_is_judged_against_mitsuba_at_its_noise_level(report):
    # the validation table: catmull's RMSE against the ground truth next to the ground truth's own noise
    table = pd.read_csv(report.parent / "tables" / "ground_truth_validation.csv")
    catmull = table[table["exact method"] == "catmull"]
    assert set(catmull["group"]) == {"edges", "stability"}
    ratio = catmull["RMSE / noise (worst frame)"]
    assert (ratio > 0.5).all() and (ratio < 1.5).all(), table
    assert (catmull["agrees within noise"] == "yes").all()
    policy = pd.read_csv(report.parent / "tables" / "ground_truth_per_group.csv")
    assert dict(zip(policy["group"], policy["Mitsuba ground truth"])) == {
        "edges": "yes", "stability": "yes", "exact reference": "NO (unvalidated)"}
    assert "compare against a reference that is not the Mitsuba ground truth" in report.read_text()


def test_figures_and_tables_come_in_paper_formats(report):
    """Every figure of a report written as 'aaeval report' writes it has its SVG and PDF."""
    root = report.parent
    pngs = {p.stem for p in (root / "figures").glob("*.png")}
    edges, stability = figure_stem("edges"), figure_stem("stability")  # group files: slug + hash of the name
    assert {f"{edges}_accuracy", f"{edges}_error_per_frame", f"{edges}_intensity_sum", f"{edges}_temporal",
            f"{edges}_space_time", f"{edges}_images", f"{stability}_stability", "ground_truth_validation"} <= pngs
    for stem in pngs:
        for fmt in ("svg", "pdf"):
            assert (root / "figures" / f"{stem}.{fmt}").stat().st_size > 0, (stem, fmt)
    tables = {p.stem for p in (root / "tables").glob("*.csv")}
    assert {"overview_error", "overview_failed", f"{figure_stem('edges')}_numbers", "ground_truth_validation"} <= tables
    for stem in tables:
        tex = (root / "tables" / f"{stem}.tex").read_text()
        assert tex.startswith("\\begin{table}") and "\\bottomrule" in tex


def test_overview_has_one_row_per_method_and_option(report):
    overview = pd.read_csv(report.parent / "tables" / "overview_error.csv")
    rows = list(overview["method and option"])
    assert rows.index("supersample:k=2") < rows.index("supersample:k=4")  # sorted by option value
    assert len(rows) == len(set(rows)) == 5  # catmull, weiler-atherton, catmull-jagged, supersample k=2, k=4


def test_failed_is_defined_once_and_stated(report):
    from aaeval.sweeps.aggregate import failure_definition

    # the page marks the threshold as the manifest's value: the words are read without the mark
    text = re.sub(r"<span class='num'[^>]*>([^<]*)</span>", r"\1", report.read_text())
    definition = failure_definition("rmse", 0.1)
    assert definition in text and "How to read this report" in text
    assert "fails when" not in text.replace(definition, "")  # no second wording anywhere


def test_accuracy_cells_times_are_never_shown(report):
    """Cells may share the machine; only a speed pass is charted (this sweep has none)."""
    text = report.read_text()
    assert "speed_accuracy" not in text and "render ms" not in text and "ms per megapixel" not in text
    assert "has no speed pass" in text


def test_viewer_data_is_self_contained_and_small(report):
    root = report.parent
    text = report.read_text()
    assert f"<script src='viewer/{figure_stem('edges')}.js'></script>" in text and "AAV.init()" in text
    page_bytes = report.stat().st_size + sum(p.stat().st_size for d in ("figures", "viewer", "tables")
                                              for p in (root / d).iterdir())
    assert page_bytes < 20e6
    assert "http://" not in text and "https://" not in text


def test_report_of_a_partial_sweep(tmp_path):
    # a group with no finished cell yet still gets its heading, and the report says what is pending
    exp = load_experiment(write_config(tmp_path))
    out = tmp_path / "sweep"
    run_sweep(exp, out, workers=1, quiet=True, cache_dir=tmp_path / "cache")
    cells = sorted((out / "cells").glob("*.json"))
    group = {p: json.loads(p.read_text())["group"] for p in cells}
    stability = [p for p in cells if group[p] == "stability"]
    assert len(stability) == 3
    for p in stability + [next(p for p in cells if group[p] == "edges")]:  # a whole group and one more cell
        p.unlink()
    write_sweep_files(SweepStore(out))  # the tables of the cells left, as a sweep writes them when it stops
    text = write_report(out, formats=("png",)).read_text()  # the page's text; the figures' twins say nothing here
    assert "5 of 9 distinct cells finished" in text and "4 pending" in text
    assert ">stability</h2>" in text  # the group with nothing finished keeps its heading


def test_pareto_front_matches_brute_force():
    rng = np.random.default_rng(3)
    t, e = rng.random(40), rng.random(40)
    dominated = [(t < t[i]) & (e < e[i]) | (t <= t[i]) & (e < e[i]) | (t < t[i]) & (e <= e[i]) for i in range(40)]
    expected = {i for i in range(40) if not dominated[i].any()}
    assert set(pareto_front(t, e).tolist()) == expected


def test_report_of_a_folder_that_is_not_a_sweep(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a sweep folder|manifest"):
        write_report(tmp_path)
