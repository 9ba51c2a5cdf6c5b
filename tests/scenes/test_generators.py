"""The one generator registry: every generator builds valid scenes; every bad parameter is
refused up front, in one line naming the generator, the parameter and the rule."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from aaeval.scenes import SceneError, parse_scene
from aaeval.scenes.generate import GENERATORS, MAX_POLYGONS, GeneratorError, generate_scene
from aaeval.scenes.shaded import has_shaded


def _inside(param, fraction):
    """A value inside a parameter's range (a fraction of the way from low to a cap)."""
    low = param.minimum if param.minimum is not None else 0.0
    high = param.maximum if param.maximum is not None else low + 50
    value = low + fraction * (min(high, low + 50) - low)
    return int(round(value)) if param.type is int else value


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_every_generator_builds_valid_scenes_across_its_difficulty_range(name):
    gen = GENERATORS[name]
    for fraction in (0.02, 0.3, 1.0):
        d = _inside(gen.difficulty_param, fraction)
        if name == "picket":
            d = 1.0 + fraction  # periods that fit the default fence
        document = generate_scene(name, d)
        scene = parse_scene(document, source=f"{name}@{d}")
        assert scene.width >= 4 and scene.height >= 4
        # something to look at: shaded objects, or polygons with one reaching into the image
        if has_shaded(scene):
            continue
        assert scene.polygons, (name, d)
        assert any(p.xy[:, 0].min() < scene.width and p.xy[:, 0].max() > 0
                   and p.xy[:, 1].min() < scene.height and p.xy[:, 1].max() > 0 for p in scene.polygons), (name, d)


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_the_difficulty_changes_the_scene(name):
    gen = GENERATORS[name]
    low, high = (1.0, 1.9) if name == "picket" else (_inside(gen.difficulty_param, 0.1), _inside(gen.difficulty_param, 0.9))
    assert low != high
    assert generate_scene(name, low) != generate_scene(name, high), f"{name}: difficulty {low} and {high} give one scene"


@pytest.mark.parametrize("name", sorted(GENERATORS))
def test_declared_defaults_are_documented_and_inside_their_own_ranges(name):
    gen = GENERATORS[name]
    assert gen.difficulty and gen.difficulty_param.doc
    for key, param in gen.params.items():
        assert param.doc, key
        assert param.convert(param.default, key) == param.default


HOSTILE = [
    # (generator, difficulty, params, words the message must contain)
    ("picket", 0, {}, ["picket", "difficulty", "(0, 1e+06]", "got 0"]),
    ("picket", -1.5, {}, ["picket", "difficulty"]),
    ("fan", 12, {"size": "x"}, ["fan", "parameter size", "integer", "'x'"]),
    ("fan", 12, {"size": 8.5}, ["parameter size", "integer"]),
    ("fan", 12, {"size": 2}, ["parameter size", "[4, 16384]"]),
    ("fan", float("nan"), {}, ["fan", "difficulty", "finite", "nan"]),
    ("sliver", float("inf"), {}, ["sliver", "difficulty", "finite"]),
    ("fan", 12, {"frames": -2}, ["parameter frames", "[1, 100000]", "-2"]),
    ("fan", 12, {"frames": True}, ["parameter frames", "True"]),
    ("fan", 12, {"step": float("nan")}, ["parameter step"]),
    ("fan", 1e7, {}, ["fan", "10000000 polygons", f"limit is {MAX_POLYGONS}"]),
    ("random", 1e12, {}, ["random", "polygons", "limit"]),
    ("random", 10, {"size": 16384, "frames": 10}, ["pixels over all frames", "limit"]),
    ("shininess", 0.5, {}, ["shininess", "difficulty", "[1, 1e+06]"]),
    ("curvature", 3, {}, ["curvature", "(0, 2]"]),
    ("curvature", 0.1, {"segments": 10**6}, ["parameter segments"]),
    ("picket", 1.0, {"bar_width": 1.0}, ["bar_width", "< 1"]),
    ("picket", 0.01, {}, ["picket", "do not fit"]),
    ("sliver", 4, {"frames": 200, "step": 1.0}, ["sliver", "drift"]),
    ("fan", 12, {"colour": [1, 0, 0]}, ["unknown parameter", "colour"]),
    ("fans", 12, {}, ["unknown scene generator", "fans"]),
]


@pytest.mark.parametrize("name, difficulty, params, words", HOSTILE)
def test_bad_generator_input_is_refused_in_one_line_before_any_work(name, difficulty, params, words):
    with pytest.raises(GeneratorError) as info:
        generate_scene(name, difficulty, **params)
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)
    assert isinstance(info.value, SceneError)  # the CLI's exit-2 family


def test_a_config_with_an_absurd_difficulty_exits_2_with_one_line(tmp_path):
    config = tmp_path / "absurd.toml"
    config.write_text(
        '[experiment]\nname = "absurd"\nreference = "catmull"\nmetrics = ["rmse"]\n\n'
        '[[groups]]\nname = "fan"\nscenes = [{generator = "fan", difficulty = [1e7], size = 9}]\n'
        'methods = ["point"]\n'
    )
    root = Path(__file__).parents[2]
    env = {**os.environ, "PYTHONPATH": str(root)}
    result = subprocess.run([sys.executable, "-m", "aaeval", "sweep", str(config), "--out", str(tmp_path / "out"),
                             "--dry-run"], capture_output=True, text=True, cwd=root, env=env, timeout=120)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr
    assert "10000000 polygons" in lines[0]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
