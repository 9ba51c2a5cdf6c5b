"""The speed pass (:mod:`aaeval.sweeps.speed`): every spec of every scene timed in interleaved
rounds whose order rotates, each timing named as the accuracy cells name the method, and a
pass kept when nothing it times has changed."""

from __future__ import annotations

import dataclasses

import pandas as pd
import pytest

from aaeval.renderers.spec import MethodSpec
from aaeval.sweeps import load_experiment
from aaeval.sweeps.speed import SPEED_FILE, accuracy_spec, read_speed, run_speed_pass, speed_identity
from tests.helpers.sweep_util import write_config

CONFIG = """
[experiment]
name = "timed"
reference = "catmull"
metrics = ["rmse"]

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], size = 12}]
methods = ["catmull", "point", "supersample"]
options.supersample = { k = [2] }

[[speed]]
accuracy = "edges"
scenes = [{generator = "edges", difficulty = [0.1], size = 256}, {generator = "fan", difficulty = [3], size = 256}]
methods = ["catmull", "point", "supersample:k=2"]
threads = 2
repeats = 3
"""


@pytest.fixture
def experiment(tmp_path):
    return load_experiment(write_config(tmp_path, CONFIG))


def test_every_spec_of_every_scene_is_timed_in_rounds_whose_order_rotates(experiment, tmp_path):
    lines = []
    frame = run_speed_pass(experiment, tmp_path / "out", log=lines.append)
    assert (tmp_path / "out" / SPEED_FILE).is_file()
    pd.testing.assert_frame_equal(read_speed(tmp_path / "out"), frame)
    specs = [str(s) for s in experiment.speed[0].specs]
    assert len(specs) == 3 and len(frame) == 2 * 3 * len(specs)
    assert frame["error"].isna().all() and (frame["render_s"] > 0).all()
    for scene, rows in frame.groupby("scene", sort=False):
        for r in range(3):
            order = list(rows[rows["round"] == r]["timed_spec"])
            assert order == specs[r:] + specs[:r], (scene, r)  # each method takes each place in turn
    pixels = frame["width"] * frame["height"]
    pd.testing.assert_series_equal(frame["ms_per_mpix"], frame["render_s"] * 1e3 / (pixels / 1e6), check_names=False)
    assert set(frame["threads"]) == {2}


def test_a_timing_is_named_as_the_accuracy_cells_name_its_method(experiment, tmp_path):
    frame = run_speed_pass(experiment, tmp_path / "out", log=lambda line: None)
    cells = {str(c.spec) for c in experiment.cells()}
    timed = dict(zip(frame["timed_spec"], frame["spec"]))
    assert timed["catmull:threads=2"] == "catmull"  # the thread count changes no pixel: paired at its default
    assert set(timed.values()) <= cells  # every timing pairs with the errors of an accuracy cell
    spec = MethodSpec.parse("catmull:threads=2")
    assert accuracy_spec(spec) == MethodSpec.parse("catmull")
    assert accuracy_spec(MethodSpec.parse("point")) == MethodSpec.parse("point")  # no threads option: as it was


def test_a_pass_of_the_same_identity_is_kept_and_force_or_a_change_times_again(experiment, tmp_path):
    out = tmp_path / "out"
    run_speed_pass(experiment, out, log=lambda line: None)
    written = (out / SPEED_FILE).read_bytes()
    lines = []
    kept = run_speed_pass(experiment, out, log=lines.append)
    assert not lines and (out / SPEED_FILE).read_bytes() == written  # nothing timed, nothing written
    pd.testing.assert_frame_equal(kept, read_speed(out))
    run_speed_pass(experiment, out, log=lines.append, force=True)
    assert any("timed renders" in line for line in lines)
    fewer = dataclasses.replace(experiment, speed=(dataclasses.replace(experiment.speed[0], repeats=2),))
    assert speed_identity(fewer) != speed_identity(experiment)
    assert len(run_speed_pass(fewer, out, log=lambda line: None)) == 2 * 2 * 3


def test_no_speed_table_means_no_pass_and_an_empty_table(tmp_path):
    experiment = load_experiment(write_config(tmp_path, CONFIG.split("[[speed]]")[0]))
    assert run_speed_pass(experiment, tmp_path / "out") is None
    assert not (tmp_path / "out").exists()
    assert read_speed(tmp_path / "out").empty
