"""Experiment configs: expansion into cells, and errors that name the file and the key."""

from __future__ import annotations

import pytest

from aaeval.sweeps import ConfigError, load_experiment
from aaeval.sweeps.table import short_label
from tests.helpers.sweep_util import SMALL, write_config


def test_small_config_expands_scenes_methods_frames(tmp_path):
    exp = load_experiment(write_config(tmp_path))
    cells = exp.cells()
    # edges: 1 scene x 2 methods x 3 frames; stability: 3 scenes x 1 method x 1 frame
    assert len(cells) == 6 + 3
    assert {short_label(c.spec) for c in cells} == {"catmull", "catmull-jagged"}
    assert sorted(c.scene_source.difficulty for c in cells if c.group == "stability") == [3, 6, 12]


def test_options_expand_only_for_methods_that_declare_them(tmp_path):
    text = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged", "supersample", "jitter:k=3"]\noptions = { k = [2, 4] }')
    specs = load_experiment(write_config(tmp_path, text)).groups[1].specs
    # jitter's k is fixed by its spec; catmull-jagged has no k; k=4 is the default, left out
    assert list(specs) == ["catmull-jagged", "supersample:k=2", "supersample", "jitter:k=3"]
    # an option that none of the methods declares is an error naming file and key
    text = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged"]\noptions = { spp = [2, 4] }')
    path = write_config(tmp_path, text, "bad.toml")
    with pytest.raises(ConfigError) as err:
        load_experiment(path)
    assert str(path) in str(err.value) and "groups[1].options" in str(err.value) and "'spp'" in str(err.value)


@pytest.mark.parametrize(
    "old, new, key",
    [
        ('reference = "catmull"', 'reference = "nosuch"', "[experiment].reference"),
        ('reference = "catmull"', 'reference = "catmull"\nrefrence = 1', "refrence"),
        ('metrics = ["rmse", "psnr"]', 'metrics = ["nosuch-metric"]', "[experiment].metrics"),
        ('temporal = ["sum_variation", "flicker"]', 'temporal = ["rmse"]', "[experiment].temporal"),
        ('fail_above = 0.1', 'fail_above = -1', "fail_above"),
        ('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged:zz=1"]', "groups[1].methods[0]"),
        ('methods = ["catmull-jagged"]', 'methods = []', "groups[1].methods"),
        ('size = 5}]', 'size = 5}]\nframes = [7]', "groups[1].frames"),
        ('{generator = "fan"', '{generator = "nosuch"', "groups[1].scenes[0].generator"),
        ('difficulty = [3, 6, 12]', 'difficulty = 3', "groups[1].scenes[0].difficulty"),
        ('name = "stability"', 'name = "edges"', "groups.name"),
        ('scenes = [{generator = "edges"', 'scenes = ["missing.toml", {generator = "edges"', "groups[0].scenes[0]"),
        ('name = "stability"', 'name = "stability"\nseeds = 3', "seeds"),
        # each key read through its Option: the rule in the words users read
        ("fail_above = 0.1", "fail_above = 0.1\nrepeats = 0",
         "[experiment].repeats: expected a whole number of timed renders from 1 to 1000, got 0"),
        ("fail_above = 0.1", 'fail_above = 0.1\nrepeats = "3"',
         "[experiment].repeats: expected a whole number of timed renders from 1 to 1000, got '3'"),
        ("fail_above = 0.1", "fail_above = nan", "[experiment].fail_above: expected a finite positive number, got nan"),
        ("fail_above = 0.1", "fail_above = true", "[experiment].fail_above: expected a finite positive number, got True"),
        ("fail_above = 0.1", 'fail_above = 0.1\nnoise_estimate = "yes"',
         "[experiment].noise_estimate: expected true or false, got 'yes'"),
        ("fail_above = 0.1", "fail_above = 0.1\nmax_seconds = inf",
         "[experiment].max_seconds: expected a number of seconds above 0 and at most 86400 (a day), got inf"),
        ('name = "small"', 'name = ""', "[experiment].name: expected a non-empty string, got ''"),
        ('reference = "catmull"\n', "", "[experiment]: missing required key 'reference'"),
        ('name = "stability"', 'name = "stability"\nrepeats = 1001',
         "groups[1].repeats: expected a whole number of timed renders from 1 to 1000, got 1001"),
        ('name = "stability"', 'name = "stability"\nanimate = 3', "groups[1].animate: expected a table"),
        ('name = "stability"', 'name = "stability"\noptions = [1]', "groups[1].options: expected a table of option"),
        ('name = "stability"\n', "", "groups[1]: missing required key 'name'"),
        ('methods = ["catmull-jagged"]', 'methods = "catmull-jagged"',
         "groups[1].methods: expected a non-empty list of method specs, got 'catmull-jagged'"),
        ('methods = ["catmull-jagged"]', "methods = [1]", "groups[1].methods: expected a non-empty list of method specs"),
        ('metrics = ["rmse", "psnr"]', "metrics = []", "[experiment].metrics: expected a non-empty list of metric names"),
        ('temporal = ["sum_variation", "flicker"]', "temporal = [1]", "[experiment].temporal: expected a list of metric"),
    ],
)
def test_errors_name_file_and_key(tmp_path, old, new, key):
    assert old in SMALL
    path = write_config(tmp_path, SMALL.replace(old, new, 1))
    with pytest.raises(ConfigError) as err:
        load_experiment(path)
    assert str(path) in str(err.value) and "\n" not in str(err.value)
    assert key in str(err.value)


def test_not_toml_and_missing_file(tmp_path):
    path = write_config(tmp_path, "[experiment\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_experiment(path)
    with pytest.raises(ConfigError, match="cannot read"):
        load_experiment(tmp_path / "absent.toml")


def test_scene_file_errors_are_reported_with_the_config_key(tmp_path):
    (tmp_path / "bad.toml").write_text("[image]\nwidth = 0\nheight = 4\n")
    path = write_config(tmp_path, SMALL.replace('scenes = [{generator = "edges"', 'scenes = ["bad.toml", {generator = "edges"'))
    with pytest.raises(ConfigError) as err:
        load_experiment(path)
    assert "groups[0].scenes[0]" in str(err.value) and "width" in str(err.value)


@pytest.mark.slow
def test_shipped_configs_are_valid():
    from pathlib import Path

    configs = sorted(Path(__file__).resolve().parents[2].joinpath("configs", "sweeps").glob("*.toml"))
    assert configs, "no experiment configs shipped"
    for path in configs:
        assert load_experiment(path).cells(), path


def test_method_scoped_options(tmp_path):
    # options.METHOD applies to that method only; naming a method not in the group is an error
    ok = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged", "catmull"]\noptions.catmull-jagged = {}')
    assert len(load_experiment(write_config(tmp_path, ok)).groups[1].specs) == 2
    bad = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged"]\noptions.supersample = { k = [2] }')
    path = write_config(tmp_path, bad, "bad.toml")
    with pytest.raises(ConfigError) as err:
        load_experiment(path)
    assert str(path) in str(err.value) and "groups[1].options.supersample" in str(err.value)
    bad = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged"]\noptions.catmull-jagged = { k = [2] }')
    path = write_config(tmp_path, bad, "bad2.toml")
    with pytest.raises(ConfigError, match=r"options.catmull-jagged: method 'catmull-jagged' has no option"):
        load_experiment(path)


def test_animate_sets_static_scenes_moving(tmp_path):
    (tmp_path / "still.toml").write_text(
        "[image]\nwidth = 6\nheight = 6\n[[polygons]]\ncolor = [1, 1, 1]\nvertices = [[1, 1, 0], [4.5, 1.2, 0], [2, 5, 0]]\n")
    text = SMALL.replace('scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]',
                         'scenes = ["still.toml"]\nanimate = { frames = 5, translate = [0.1, 0.05] }')
    exp = load_experiment(write_config(tmp_path, text))
    edges = [c for c in exp.cells() if c.group == "edges"]
    assert sorted({c.frame for c in edges}) == [0, 1, 2, 3, 4]
    assert edges[0].scene_source.parsed.frames == 5
    bad = text.replace("translate = [0.1, 0.05]", "translate = [0.1]")
    path = write_config(tmp_path, bad, "bad.toml")
    with pytest.raises(ConfigError) as err:
        load_experiment(path)
    assert str(path) in str(err.value) and "groups[0].animate" in str(err.value)
