"""One render path: every timed render goes through
``aaeval.renderers.run.render_timed``, with one budget check per call, one warm-up
cache, and a spec read from its text once where it enters."""

from __future__ import annotations

from pathlib import Path

import pytest

import aaeval.renderers.run as run
import aaeval.renderers.spec as spec_module
from aaeval.renderers import MethodError, MethodSpec
from aaeval.scenes import parse_scene

TRIANGLE = {"image": {"width": 5, "height": 4},
            "polygons": [{"color": [1, 0, 0], "vertices": [[0.5, 0.5, 1], [4.5, 1, 1], [2, 3.5, 1]]}]}


@pytest.fixture
def renders(monkeypatch):
    """Every render of this test, in order: ("warm", spec) untimed, ("timed", spec) on the
    clock; and the budget checks. The process's warm-up cache starts empty."""
    calls, checks, state = [], [], {"rehearsing": False}
    real_rehearse, real_timed, real_check = run._rehearse, run._timed, run.check_budget

    def rehearse(scene, spec):
        state["rehearsing"] = True
        try:
            return real_rehearse(scene, spec)
        finally:
            state["rehearsing"] = False

    def timed(scene, spec):
        calls.append(("warm" if state["rehearsing"] else "timed", str(spec)))
        return real_timed(scene, spec)

    monkeypatch.setattr(run, "_rehearse", rehearse)
    monkeypatch.setattr(run, "_timed", timed)
    monkeypatch.setattr(run, "check_budget", lambda *a: checks.append(a[1].name) or real_check(*a))
    monkeypatch.setattr(run, "_warmed", set())
    return calls, checks


def test_a_measured_spec_is_rendered_untimed_first_with_every_option(renders):
    """Catmull's own warm-up compiles the box path only; a timed
    catmull:filter=tent (or any other option) must have rendered that very spec untimed first."""
    from aaeval.sweeps import measure

    calls, checks = renders
    scene = parse_scene(TRIANGLE)
    specs = [MethodSpec.parse(s) for s in ("catmull:filter=tent", "catmull:filter=gaussian",
                                            "supersample:k=2,filter=mitchell", "catmull")]
    for spec in specs:
        measure.render_measured(scene, spec, 0, repeats=2)
    for spec in specs:
        timed = [i for i, c in enumerate(calls) if c == ("timed", spec)]
        assert len(timed) == 2
        assert calls.index(("warm", spec)) < timed[0], spec  # this very spec, untimed, before its clock
    assert len(checks) == len(specs)  # one budget check per cell, not one per render
    calls.clear()
    measure.render_measured(scene, MethodSpec.parse("catmull:filter=tent"), 0)
    assert calls == [("timed", "catmull:filter=tent")]  # once per process and size
    bigger = parse_scene({"image": {"width": 6, "height": 4}, "polygons": []})
    measure.render_measured(bigger, MethodSpec.parse("catmull:filter=tent"), 0)
    assert calls[1:] == [("warm", "catmull:filter=tent"), ("timed", "catmull:filter=tent")]


def test_render_timed_checks_the_budget_once_before_any_render(renders, monkeypatch):
    calls, checks = renders
    scene = parse_scene(TRIANGLE)
    image, seconds = run.render_timed(scene, "point", repeats=3, rehearse=True)
    assert image.shape == (4, 5, 3) and len(seconds) == 3 and all(s >= 0 for s in seconds)
    assert checks == ["point"] and calls == [("warm", "point")] + [("timed", "point")] * 3
    monkeypatch.setenv("AAEVAL_MAX_SAMPLES", "10")  # 20 pixels x 16 samples: refused before any render
    calls.clear()
    with pytest.raises(MethodError, match="AAEVAL_MAX_SAMPLES"):
        run.render_timed(scene, "supersample:k=4", repeats=3, rehearse=True)
    assert calls == []
    with pytest.raises(ValueError, match="repeats must be a whole number >= 1"):
        run.render_timed(scene, "point", repeats=0)


@pytest.mark.parametrize("stats", [True, False])
def test_render_stats_warms_up_the_spec_it_times(tmp_path, renders, stats):
    from aaeval.cli import main

    calls, _ = renders
    scene = Path(__file__).resolve().parents[2] / "configs" / "scenes" / "fan.toml"
    extra = ["--stats", str(tmp_path / "s.json")] if stats else []
    assert main(["render", str(scene), "-m", "catmull:filter=bspline", "-o", str(tmp_path / "f.npy"), *extra]) == 0
    rehearsed = [("warm", "catmull:filter=bspline")] if stats else []
    assert calls == rehearsed + [("timed", "catmull:filter=bspline")]


def test_a_config_reads_each_spec_text_once_and_sets_cache_as_an_option(monkeypatch):
    from aaeval.sweeps import cells

    read = []
    real = spec_module.parse_spec
    for module in (cells, spec_module):  # the config's own reading, and MethodSpec.parse's
        monkeypatch.setattr(module, "parse_spec", lambda text: read.append(text) or real(text))
    methods = ["mitsuba:spp=4", "mitsuba:spp=8,cache=true", "supersample"]
    got = cells.expand_specs(methods, {"seed": [1, 2], "k": [2, 3]}, "groups[0]", with_given=True)
    assert read == methods  # each text read once; nothing spliced into it and read again
    monkeypatch.undo()
    expected = [MethodSpec.parse("mitsuba:spp=4,cache=false,seed=1"), MethodSpec.parse("mitsuba:spp=4,cache=false,seed=2"),
                MethodSpec.parse("mitsuba:spp=8,cache=true,seed=1"), MethodSpec.parse("mitsuba:spp=8,cache=true,seed=2"),
                MethodSpec.parse("supersample:k=2"), MethodSpec.parse("supersample:k=3")]
    assert [spec for spec, _ in got] == expected
    assert [str(spec) for spec, _ in got][0] == "mitsuba:cache=False,seed=1,spp=4"  # the canonical text keys use
    assert got[0][1] == {"spp", "cache", "seed"} and got[-1][1] == {"k"}
