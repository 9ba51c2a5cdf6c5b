"""Sub-pixel phases of an animation (docs/scene_format.md, ``phases``)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from aaeval.catmull import render_flat
from aaeval.sweeps.config import parse_experiment
from aaeval.sweeps.config_keys import ConfigError
from aaeval.renderers import MethodSpec, render
from aaeval.scenes import SceneError, load_scene, parse_scene
from aaeval.scenes.phases import R2_STEP, phase_offsets

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "configs" / "scenes"


def _fence(name="picket_fence", **animation):
    document = tomllib.loads((SCENES / f"{name}.toml").read_text())
    document["animation"] = animation
    return parse_scene(document, source=name)


def test_r2_offsets_are_the_plastic_number_recurrence():
    g = 1.0
    for _ in range(200):  # the real root of g**3 = g + 1, by fixed-point iteration
        g = (g + 1.0) ** (1.0 / 3.0)
    assert np.allclose(R2_STEP, [1 / g, 1 / g**2], rtol=0, atol=1e-15)
    offsets = phase_offsets("r2", 5)
    assert np.array_equal(offsets[0], [0.0, 0.0])
    assert np.allclose(offsets[3], np.mod(3 * R2_STEP, 1.0))


def test_random_offsets_are_seeded_start_at_zero_and_do_not_depend_on_the_frame_count():
    a, b = phase_offsets("random", 10, seed=3), phase_offsets("random", 40, seed=3)
    assert np.array_equal(a, b[:10]) and np.array_equal(a[0], [0.0, 0.0])
    assert ((a[1:] >= 0) & (a[1:] < 1)).all()
    assert not np.array_equal(a, phase_offsets("random", 10, seed=4))


def test_a_file_without_phases_moves_exactly_as_before():
    scene = load_scene(SCENES / "picket_fence.toml")
    assert scene.phases == "none"
    for k in (0, 5, 15):
        moved = scene.at_frame(k)
        first = scene.polygons[0].vertices
        assert np.array_equal(moved.polygons[0].vertices[:, :2], first[:, :2] + k * scene.translate)


def test_phases_move_frame_k_by_its_offset_and_keep_the_exact_sum():
    scene = _fence(frames=12, phases="random", seed=2)
    offsets = phase_offsets("random", 12, seed=2)
    first = scene.polygons[0].vertices[:, :2]
    for k in (0, 3, 11):
        assert np.allclose(scene.at_frame(k).polygons[0].vertices[:, :2], first + offsets[k], atol=1e-12)
        # 20 bars of 0.3 x 6 px, white: 108 whatever the phase (the fence stays inside the image)
        assert render_flat(scene.at_frame(k)).sum() == pytest.approx(108.0, rel=1e-12)
    # frames of a moved scene are relative to where it is: at_frame(a).at_frame(b) == at_frame(b)
    assert np.allclose(scene.at_frame(7).at_frame(3).polygons[0].vertices, scene.at_frame(3).polygons[0].vertices)


def test_a_commensurate_step_hides_the_regular_grids_variation_and_random_phases_show_it():
    spec = MethodSpec.parse("supersample:k=4")

    def sums(scene):
        return np.array([render(scene, spec, frame=k).sum() for k in range(scene.frames)])

    stepped = sums(load_scene(SCENES / "picket_fence.toml"))
    assert np.ptp(stepped) == 0.0 and stepped[0] == pytest.approx(90.0)  # 1/16-px steps: 90 every frame
    phased = sums(_fence(frames=32, phases="random", seed=1))
    assert np.ptp(phased) / phased.mean() > 0.5  # one or two sample columns per bar: 90 or 180


@pytest.mark.parametrize("animation, words", [
    ({"frames": 4, "phases": "halton"}, "phases"),
    ({"frames": 4, "phases": 1}, "phases"),
    ({"frames": 4, "phases": "r2", "seed": 1}, "only phases = \"random\" takes a seed"),
    ({"frames": 4, "phases": "random", "seed": -1}, "seed"),
    ({"frames": 4, "phases": "random", "seed": True}, "seed"),
])
def test_bad_phases_are_one_line_errors(animation, words):
    with pytest.raises(SceneError, match=words):
        _fence(**animation)


def test_an_experiments_animate_takes_phases_and_refuses_unknown_keys(tmp_path):
    fence = str(SCENES / "picket_fence.toml")
    doc = {"experiment": {"reference": "catmull", "metrics": ["rmse"]},
           "groups": [{"name": "g", "scenes": [fence], "methods": ["point"],
                       "animate": {"frames": 5, "phases": "random", "seed": 7}}]}
    scene = parse_experiment(doc).groups[0].scenes[0].parsed
    assert (scene.frames, scene.phases, scene.phase_seed) == (5, "random", 7)
    doc["groups"][0]["animate"] = {"frames": 5, "jitter": "r2"}
    with pytest.raises(ConfigError, match="jitter"):
        parse_experiment(doc)
    doc["groups"][0]["animate"] = {"frames": 5, "phases": "sobol"}
    with pytest.raises(ConfigError, match="phases"):
        parse_experiment(doc)


def test_written_scenes_keep_their_phases(tmp_path):
    from aaeval.scenes.write import write_scene

    scene = _fence(frames=6, translate=[0.01, 0.0], phases="random", seed=5)
    path = write_scene(scene, tmp_path / "fence.toml")
    back = load_scene(path)
    assert (back.phases, back.phase_seed) == ("random", 5)
    assert np.allclose(back.at_frame(4).polygons[3].vertices, scene.at_frame(4).polygons[3].vertices)
