"""A method spec is parsed once, where it enters, and carries one label rule everywhere."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import aaeval.renderers.spec as spec_module
from aaeval.sweeps import load_experiment, run_sweep
from aaeval.sweeps.report_files import rebuild_results
from aaeval.sweeps.store import SweepStore
from aaeval.renderers import MethodError, MethodSpec, render
from aaeval.scenes import parse_scene
from aaeval.scenes.generate import generate_scene


def test_a_spec_is_its_canonical_string_and_carries_its_method_and_options():
    spec = MethodSpec.parse(" catmull:specular=none ")
    assert spec == "catmull" and isinstance(spec, str) and spec.name == "catmull"
    assert spec.options["specular"] == "none" and spec.options["filter"] == "box"
    with pytest.raises(TypeError):
        spec.options["filter"] = "tent"  # read-only: a spec is a value
    assert MethodSpec.parse("supersample: k = 2") == "supersample:k=2"
    assert MethodSpec.parse(spec) is spec  # a parsed spec is never parsed again
    assert spec.with_options(filter="tent") == "catmull:filter=tent"
    with pytest.raises(MethodError, match="unknown option"):
        spec.with_options(bogus=1)


def test_one_label_rule():
    jitter = MethodSpec.parse("jitter:seed=1")
    assert jitter.label() == "jitter:seed=1"  # options at their defaults are left out...
    assert jitter.label({"k"}) == "jitter:k=4,seed=1"  # ...unless they vary among the rows shown
    mitsuba = MethodSpec.parse("mitsuba:cache=false,spp=16")
    assert "cache" in mitsuba and mitsuba.label() == "mitsuba:spp=16"  # incidental: in the record, not the label


def test_a_spec_crosses_a_process_boundary_as_its_string():
    spec = MethodSpec.parse("supersample:k=2")
    back = pickle.loads(pickle.dumps(spec))
    assert back == spec and back.method is spec.method and dict(back.options) == dict(spec.options)


def test_render_takes_a_string_or_a_spec():
    scene = parse_scene(generate_scene("fan", 5, size=9))
    assert np.array_equal(render(scene, "point"), render(scene, MethodSpec.parse("point")))


CONFIG = """
[experiment]
name = "once"
reference = "catmull"
metrics = ["rmse"]

[[groups]]
name = "g"
scenes = [{generator = "fan", difficulty = [5], size = 9, frames = 2}]
methods = ["point", "jitter"]
options.jitter = { seed = [0, 1] }

[[groups]]
name = "h"
scenes = [{generator = "fan", difficulty = [7], size = 9}]
methods = ["jitter"]
"""


@pytest.mark.slow
def test_a_sweep_parses_its_specs_only_where_the_config_is_read(tmp_path, monkeypatch):
    config = tmp_path / "exp.toml"
    config.write_text(CONFIG)
    experiment = load_experiment(config)
    assert all(isinstance(s, MethodSpec) for g in experiment.groups for s in (*g.specs, g.reference))
    calls = []
    real = spec_module.parse_spec
    monkeypatch.setattr(spec_module, "parse_spec", lambda text: calls.append(text) or real(text))
    run_sweep(experiment, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    monkeypatch.undo()
    results, _ = rebuild_results(SweepStore(tmp_path / "out"))
    # planning, references, warm-up, timed renders and records use the parsed specs, and the
    # results table, built from the records on disk at the end, finds each stored spec's text
    # parsed already in this process: no text is parsed again
    assert sorted(set(results["spec"])) == ["jitter", "jitter:seed=1", "point"]
    assert calls == []
    # one label per spec, whichever group, table, figure or view shows it: the options that
    # differ from the defaults or vary among the method's rows anywhere in the sweep
    labels = results.groupby("spec")["label"].unique().map(list).to_dict()
    assert labels == {"jitter": ["jitter:seed=0"], "jitter:seed=1": ["jitter:seed=1"], "point": ["point"]}
