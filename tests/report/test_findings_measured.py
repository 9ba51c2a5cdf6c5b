"""The findings read what was measured, whatever the groups are called, and an
experiment that names no metrics measures every one that applies to its scenes."""

from __future__ import annotations

import re

import pytest

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.sweeps.config import parse_experiment
from aaeval.metrics import METRICS, default_metrics
from aaeval.report import write_report
from aaeval.report.findings import QUESTIONS

pytestmark = pytest.mark.xdist_group("findings_measured")

CONFIG = """
[experiment]
name = "mine"
reference = "mitsuba:sampler=stratified,spp=64,seed=0"

[[groups]]
name = "my-moving-bars"
scenes = [{generator = "edges", difficulty = [0.1], size = 12}]
animate = { frames = 3, phases = "random", seed = 1 }
methods = ["catmull", "point"]

[[groups]]
name = "my-shiny-tube"
reference = "mitsuba:spp=64,seed=0"
scenes = [{generator = "shininess", difficulty = [500], size = 16, frames = 3}]
methods = ["catmull"]
options.catmull = { specular = ["none", "amanatides"] }

[[speed]]
scenes = [{generator = "random", difficulty = [20], size = 256}]
methods = ["catmull", "point"]
repeats = 1

[[speed]]
scenes = [{generator = "shininess", difficulty = [500], size = 256}]
methods = ["catmull"]
options.catmull = { specular = ["none", "amanatides"] }
repeats = 1
"""


def test_no_metric_list_means_every_metric_that_applies():
    doc = {"experiment": {"reference": "catmull"},
           "groups": [{"name": "flat", "scenes": [{"generator": "edges", "difficulty": [0.1], "size": 8,
                                                     "frames": 2}], "methods": ["point"]},
                      {"name": "still", "scenes": [{"generator": "fan", "difficulty": [3], "size": 8}],
                       "methods": ["point"]}]}
    flat, still = parse_experiment(doc).groups
    images = [n for n, m in METRICS.items() if m.kind == "image"]
    # a flat scene: every image metric but those over highlights (none there)
    assert set(flat.metrics) == {n for n in images if METRICS[n].mask != "highlight"}
    assert "edge_rmse" in flat.metrics and "highlight_rmse" not in flat.metrics
    assert {"sum_variation", "sum_bias", "flicker", "temporal_bias"} <= set(flat.temporal)
    assert "highlight_profile_flicker" not in flat.temporal
    assert still.temporal == ()  # nothing moves: nothing to measure over frames
    assert flat.metrics == default_metrics("image", [src.parsed for src in flat.scenes])


@pytest.mark.slow
def test_a_users_experiment_with_its_own_group_names_gets_every_findings_table(tmp_path):
    config = tmp_path / "mine.toml"
    config.write_text(CONFIG)
    out = tmp_path / "sweep"
    run_sweep(load_experiment(config), out, workers=1, quiet=True, cache_dir=tmp_path / "cache")
    write_report(out, formats=("png", "svg"))  # the SVG: its text shows which methods a figure draws
    page = (out / "index.html").read_text()
    findings = page[page.index("<h2 id='findings'>"):page.index("<h2 id='how-to-read'>")]
    sections = {part.split("'", 1)[0]: part for part in findings.split("<h3 id='finding-")[1:]}
    assert set(sections) == {q.key for q in QUESTIONS}
    for key, section in sections.items():
        assert "Not measured" not in section, key
        assert "<table class='findings' data-group=" in section, key
    # each question answered by the group that measured it
    assert re.search(r"Edge aliasing \(edge RMSE, group my-moving-bars\)", findings)
    assert re.search(r"Highlight aliasing \(hl RMSE, group my-shiny-tube\)", findings)
    assert "sum bias (typical frame)" in findings
    # a phase figure for each animated group, every method drawn in it
    for stem in ("my_moving_bars", "my_shiny_tube"):
        svg = [p for p in (out / "figures").iterdir() if p.name.startswith(stem) and p.name.endswith("_phase.svg")]
        assert len(svg) == 1, stem
        assert "method=catmull" in svg[0].read_text()
    assert "method=point;" in next((out / "figures").glob("my_moving_bars*_phase.svg")).read_text()
