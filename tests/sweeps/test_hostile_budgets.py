"""Budgets for every cost a user can choose, and option values refused at the check: a
crow supersampling factor against the memory limit, phase offsets of any frame in constant
memory, compare's repeats against the time limit, integers past int64 and values outside an
option's range (each one line, before any work)."""

from __future__ import annotations

import json
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from aaeval import registries
from aaeval.cli import main
from aaeval.renderers import MethodError, MethodSpec
from aaeval.renderers.budget import check_budget
from aaeval.scenes import SceneError, load_scene, parse_scene
from aaeval.scenes.phases import phase_offset, phase_offsets
from tests.helpers.sweep_util import SMALL, write_config

ROOT = Path(__file__).resolve().parents[2]
THIN = ROOT / "configs" / "scenes" / "shaded" / "thin-highlight.toml"
FAN = ROOT / "configs" / "scenes" / "fan.toml"
BIG = "9" * 400

registries.load()


# --- phases: one frame's offset, the same numbers, constant memory -----------------------

@pytest.mark.parametrize("kind", ["none", "r2", "random"])
@pytest.mark.parametrize("seed", [0, 7, 2**40 + 3])
def test_one_frames_offset_is_that_row_of_every_frames_offsets(kind, seed):
    every = phase_offsets(kind, 500, seed)  # the oracle: every earlier frame drawn first
    one = np.array([phase_offset(kind, k, seed) for k in range(500)])
    np.testing.assert_array_equal(one, every)


def test_a_far_frame_of_a_random_phase_scene_costs_no_more_than_frame_one():
    scene = parse_scene({"image": {"width": 1, "height": 1, "background": [0, 0, 0]},
                         "animation": {"frames": 100_000_000, "translate": [0.0, 0.0], "phases": "random"},
                         "polygons": [{"color": [1, 1, 1], "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}]})
    tracemalloc.start()
    try:
        start = time.perf_counter()
        far = scene.at_frame(99_999_999)
        took = time.perf_counter() - start
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20  # the offsets of every earlier frame were 1.6 GB
    assert took < 5  # a hang guard, not a timing claim
    shift = far.arrays.vertices[0, :2] - scene.arrays.vertices[0, :2]
    np.testing.assert_array_equal(shift, phase_offset("random", 99_999_999, 0))
    assert np.all((shift >= 0) & (shift < 1))


# --- crow: the magnified scene it draws is budgeted ---------------------------------------

def test_crow_past_the_memory_limit_is_refused_before_work(monkeypatch):
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "512M")
    scene = load_scene(THIN)
    spec = MethodSpec.parse("catmull:specular=crow,k=1000")
    with pytest.raises(MethodError, match=r"needs about .* GiB of memory.*0.5 GiB available"):
        check_budget(scene, spec.method, spec.options)
    small = MethodSpec.parse("catmull:specular=crow,k=4")
    check_budget(scene, small.method, small.options)  # the default factor fits


@pytest.mark.slow
def test_crows_memory_estimate_bounds_what_it_takes():
    """The estimate against the resident memory a render adds, sampled from /proc while it
    runs in a fresh process (the process's high-water mark would count its imports' peak)."""
    code = f"""
import json, os, threading, time
from aaeval import registries
registries.load()
from aaeval.renderers import MethodSpec, render
from aaeval.scenes import load_scene

def resident():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

scene = load_scene({str(THIN)!r})
render(scene, "catmull:specular=crow,k=1,region=all,threads=1")
base, peak, done = resident(), [0], threading.Event()

def sample():
    while not done.is_set():
        peak[0] = max(peak[0], resident())
        time.sleep(0.002)

watcher = threading.Thread(target=sample)
watcher.start()
render(scene, "catmull:specular=crow,k=48,region=all,threads=1")
done.set()
watcher.join()
spec = MethodSpec.parse("catmull:specular=crow,k=48,region=all")
print(json.dumps({{"taken": peak[0] - base, "estimate": spec.method.memory(scene, spec.options)}}))
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr
    got = json.loads(done.stdout.strip().splitlines()[-1])
    # it did draw the magnified scene (40 x 40 x 48^2 pixels: about 370 MB on an idle machine)
    assert got["taken"] > 100e6, got
    assert got["taken"] <= got["estimate"] <= 3 * got["taken"], got


# --- compare's repeats ----------------------------------------------------------------------

def test_compare_repeats_past_the_time_limit_are_refused_before_work(capsys):
    code = main(["compare", str(FAN), "-m", "point", "-r", "catmull", "--repeats", "1000000000", "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "--repeats 1000000000" in err and "over the limit" in err and err.count("\n") == 1
    code = main(["compare", str(FAN), "-m", "point", "-r", "catmull", "--repeats", BIG, "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "--repeats must be a whole number" in err and err.count("\n") == 1
    import aaeval

    with pytest.raises(SceneError, match="1000000000 repeats"):
        aaeval.compare(FAN, "point", repeats=10**9)


# --- option values: past int64, outside the range -------------------------------------------

@pytest.mark.parametrize("spec, rule", [
    (f"supersample:k={BIG}", "integer of 1329 bits, past the largest taken"),
    (f"jitter:seed={BIG}", "integer of 1329 bits, past the largest taken"),
    (f"supersample:k={'9' * 5000}", "expected int"),
    (f"catmull:specular=crow,power={BIG}", "must be a finite number in"),
    ("catmull:specular=amanatides,power=2", "'power': must be a finite number in [1e-06, 1]"),
    ("catmull:threads=5000", "'threads': must be an integer in [0, 4096]"),
])
def test_an_option_value_out_of_range_is_refused_at_the_spec(spec, rule, capsys, tmp_path):
    with pytest.raises(MethodError) as caught:
        MethodSpec.parse(spec)
    assert rule in str(caught.value) and "\n" not in str(caught.value)
    assert main(["render", str(FAN), "-m", spec, "-o", str(tmp_path / "never.png")]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("old, new, rule", [
    ('methods = ["catmull", "catmull-jagged"]', 'methods = ["catmull:specular=amanatides,power=2"]',
     "groups[0].methods[0]: method 'catmull' option 'power'"),
    ('methods = ["catmull", "catmull-jagged"]', 'methods = ["catmull:threads=5000"]',
     "groups[0].methods[0]: method 'catmull' option 'threads'"),
    ("frames = 3, size = 12", f"frames = 3, size = {BIG}", "parameter size: an integer of 1329 bits"),
    ("difficulty = [0.1]", f"difficulty = [{BIG}]", "difficulty"),
    ("fail_above = 0.1", "fail_above = 0.1\n[[speed]]\nscenes = [{generator = \"edges\", difficulty = [0.1], "
     "size = 256}]\nmethods = [\"catmull\"]\nthreads = 5000", "speed[0].threads: expected a whole number of threads"),
])
def test_a_config_value_out_of_range_is_refused_at_the_config_check(tmp_path, capsys, old, new, rule):
    assert old in SMALL
    config = write_config(tmp_path, SMALL.replace(old, new, 1))
    code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "-q"])
    err = capsys.readouterr().err
    assert code == 2 and rule in err and err.count("\n") == 1, err
    assert not (tmp_path / "out").exists()
