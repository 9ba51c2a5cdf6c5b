"""The HTML report: every link resolves, every comparison names its reference."""

from __future__ import annotations

from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlparse

import numpy as np
import pytest

from aaeval.experiments import load_experiment, run_sweep
from aaeval.report import write_report
from aaeval.report.figures import pareto_front
from sweep_util import write_config


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


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("report")
    exp = load_experiment(write_config(tmp))
    out = tmp / "sweep"
    run_sweep(exp, out, workers=1, quiet=True, cache_dir=tmp / "cache")
    return write_report(out)


def test_every_link_resolves(report):
    parser = _Links()
    parser.feed(report.read_text())
    imgs = [link for tag, link in parser.links if tag == "img"]
    assert len(imgs) >= 5  # speed-accuracy, intensity sum, temporal (flicker), stability, image grids
    for tag, link in parser.links:
        url = urlparse(link)
        assert not url.scheme and not url.netloc, f"report must be self-contained: {link}"
        if link.startswith("#"):
            assert link[1:] in parser.ids, link
            continue
        target = report.parent / unquote(url.path)
        assert target.is_file() and target.stat().st_size > 0, f"{tag} {link} does not resolve"


def test_every_figure_states_its_reference(report):
    parser = _Links()
    parser.feed(report.read_text())
    assert parser.figcaptions
    for caption in parser.figcaptions:
        assert "Reference: catmull (exact; noise 0)" in caption, caption


def test_report_has_the_expected_charts_and_tables(report):
    from aaeval.report.names import figure_stem

    figures = {p.name for p in (report.parent / "figures").glob("*.png")}
    edges, stability = figure_stem("edges"), figure_stem("stability")
    assert {f"{edges}_speed_accuracy.png", f"{edges}_intensity_sum.png", f"{edges}_temporal.png",
            f"{stability}_stability.png", f"{edges}_images.png"} <= figures
    text = report.read_text()
    assert "<table>" in text and "catmull-jagged" in text and "9 of 9 distinct cells finished" in text


def test_report_of_a_partial_sweep(tmp_path):
    # a group with no finished cell yet still gets its heading, and the report says what is pending
    exp = load_experiment(write_config(tmp_path))
    out = tmp_path / "sweep"
    run_sweep(exp, out, workers=1, quiet=True, cache_dir=tmp_path / "cache")
    for p in sorted((out / "cells").glob("*.json"))[:4]:
        p.unlink()
    text = write_report(out).read_text()
    assert "5 of 9 distinct cells finished" in text and "4 pending" in text


def test_pareto_front_matches_brute_force():
    rng = np.random.default_rng(3)
    t, e = rng.random(40), rng.random(40)
    dominated = [(t < t[i]) & (e < e[i]) | (t <= t[i]) & (e < e[i]) | (t < t[i]) & (e <= e[i]) for i in range(40)]
    expected = {i for i in range(40) if not dominated[i].any()}
    assert set(pareto_front(t, e).tolist()) == expected


def test_report_of_a_folder_that_is_not_a_sweep(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a sweep folder|manifest"):
        write_report(tmp_path)


def test_labels_show_options_that_vary_even_at_their_default():
    from aaeval.experiments.table import short_label

    assert short_label("supersample") == "supersample"
    assert short_label("supersample", {"k"}) == "supersample:k=4"
    assert short_label("mitsuba:spp=64,cache=false,seed=1") == "mitsuba:seed=1,spp=64"
