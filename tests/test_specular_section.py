"""The specular section of the report: figures written, every method present, honest labels."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from aaeval.report.specular_section import HIGHLIGHT_THRESHOLD, flicker, specular_section
from aaeval.specular.methods import SPECULAR_METHODS

SCENE = """
[image]
width = 20
height = 16
background = [0.02, 0.02, 0.03]

[animation]
frames = 3
translate = [0.137, 0.061]

[shaded.light]
type = "directional"
direction = [0.3, 0.0, -1.0]

[[shaded.cylinders]]
centre = [10.2, 8.1, 40.0]
axis = [0.12, 1.0, 0.0]
radius = 5.0
length = 12.0
segments = 24
spin = { axis = [0.0, 0.0, 1.0], degrees = 0.3 }
material = { color = [0.75, 0.12, 0.10], ka = 0.15, kd = 0.55, ks = 0.8, n = 300 }
"""


def test_flicker_ignores_a_steady_bias_and_measures_what_changes():
    truth = np.array([10.0, 11.0, 12.0, 11.0])
    assert flicker(truth * 0 + truth - 2.0, truth) == 0.0
    wobble = truth + np.array([1.0, -1.0, 1.0, -1.0])
    assert flicker(wobble, truth) == pytest.approx(1.0 / 11.0)


def test_no_section_for_a_sweep_without_shaded_scenes(tmp_path):
    assert specular_section(tmp_path, tmp_path / "figures") == ""
    (tmp_path / "manifest.json").write_text(json.dumps({"scenes": {"d": {"document": {"image": {}}}}}))
    assert specular_section(tmp_path, tmp_path / "figures") == ""
    assert not (tmp_path / "figures").exists()


def test_a_sweep_with_shaded_scenes_gets_the_section(tmp_path):
    from aaeval.report.specular_section import _sweep_has_shaded_scenes
    from aaeval.scenes.generate import generate_scene

    documents = {"a": {"source": "fan", "document": generate_scene("fan", 6)},
                 "b": {"source": "shininess", "document": generate_scene("shininess", 50)}}
    (tmp_path / "manifest.json").write_text(json.dumps({"scenes": documents}))
    assert _sweep_has_shaded_scenes(tmp_path)


@pytest.fixture(scope="module")
def section(tmp_path_factory):
    """The section of a tiny animated cylinder, built once (figures cost seconds each)."""
    tmp = tmp_path_factory.mktemp("specular_section")
    scene = tmp / "tiny_cylinder.toml"
    scene.write_text(SCENE)
    out = tmp / "report"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("AAEVAL_CACHE_DIR", str(tmp / "cache"))
        text = specular_section(out, out / "figures", force=True, scenes=[scene], spp=16, frames=3)
    return out, text


def test_section_draws_every_method_against_the_stated_truth(section):
    out, text = section
    assert "16 spp" in text and "seed 0" in text and "seed 1" in text and str(HIGHLIGHT_THRESHOLD) in text
    for name in SPECULAR_METHODS:
        assert f"catmull:specular={name}" in text
    sources = re.findall(r"<img src='([^']+)'", text)
    assert len(sources) == 6  # two tables, one plate, detection, highlight error, energy
    for src in sources:
        png = out / src
        for fmt in (".png", ".svg", ".pdf"):
            assert png.with_suffix(fmt).stat().st_size > 1000, (src, fmt)
    assert text.count("<tr>") == 1 + len(SPECULAR_METHODS) + 1  # header, each method, amanatides P=0.999


def test_section_curves_carry_the_reports_method_tags(section):
    """Every curve of a method is tagged like the report's own figures (same style table)."""
    out, _ = section
    svg = next((out / "figures").glob("specular_energy_*.svg")).read_text()
    tags = re.findall(r"""id=["']method=catmull;options=""", svg)  # matplotlib's quoting differs by version
    assert len(tags) == len(SPECULAR_METHODS) + 1  # and amanatides P=0.999
