"""Running sweeps: results survive reruns, kills and failing cells."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from aaeval.sweeps import SweepStore, load_experiment, plan, run_sweep
from aaeval.renderers import METHODS, register_method, render
from tests.helpers.sweep_util import SMALL, slow_config, slow_sweep, write_config

ROOT = Path(__file__).resolve().parents[2]

def _fails_on_fans(scene):
    if len(scene.polygons) > 4:
        raise RuntimeError("too many polygons for this test method")
    return render(scene, "catmull")


def _slow(scene):
    time.sleep(0.25)
    return render(scene, "catmull")


@pytest.fixture
def test_methods():
    """Methods for these tests only, removed afterwards so other tests never see them."""
    added = {"test-fails-on-fans": _fails_on_fans, "test-slow": _slow}
    for name, func in added.items():
        register_method(name, func, summary="test only")
    yield
    for name in added:
        METHODS.unregister(name)


def _run(tmp_path, text=SMALL, **kw):
    exp = load_experiment(write_config(tmp_path, text))
    out = tmp_path / "out"
    return exp, out, run_sweep(exp, out, workers=1, quiet=True, cache_dir=tmp_path / "cache", **kw)


def test_sweep_writes_one_file_per_cell_and_a_tidy_table(tmp_path):
    exp, out, summary = _run(tmp_path)
    assert summary.total == summary.ran == 9 and summary.failed == 0 and not summary.lost
    store = SweepStore(out)
    assert len(store.finished()) == 9
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 9
    for col in ("scene", "method", "options", "frame", "rmse", "render_s", "host", "error", "reference",
                "reference_noise_rmse", "difficulty"):
        assert col in table.columns, col
    exact = table[table["method"] == "catmull"]
    assert (exact["rmse"] == 0).all()  # catmull against the catmull reference: same numbers
    assert (table[table["method"] == "catmull-jagged"]["rmse"] > 0).all()
    # the stored image is what the method renders
    row = exact.iloc[0]
    scene = next(c.scene_source for c in exp.cells() if c.scene_source.name == row["scene"]).parsed
    np.testing.assert_array_equal(store.load_image(row["key"]), render(scene, "catmull", frame=int(row["frame"])))
    temporal = pd.read_parquet(out / "temporal.parquet")
    assert set(temporal["label"]) == {"catmull", "catmull-jagged"}
    assert temporal.set_index("label").loc["catmull", "sum_variation"] < 1e-12


@pytest.mark.slow
def test_rerun_skips_finished_cells_and_runs_new_ones(tmp_path):
    exp, out, first = _run(tmp_path)
    stamps = {p.name: p.stat().st_mtime_ns for p in (out / "cells").glob("*.json")}
    _, _, second = _run(tmp_path)
    assert second.skipped == 9 and second.ran == 0
    assert {p.name: p.stat().st_mtime_ns for p in (out / "cells").glob("*.json")} == stamps
    # a config that grows runs only the new cells
    bigger = SMALL.replace("difficulty = [3, 6, 12]", "difficulty = [3, 6, 12, 24]")
    _, _, third = _run(tmp_path, bigger)
    assert third.skipped == 9 and third.ran == 1
    assert {p.name: p.stat().st_mtime_ns for p in (out / "cells").glob("*.json") if p.name in stamps} == stamps


@pytest.mark.slow
def test_reference_cache_is_shared_between_sweeps(tmp_path):
    _run(tmp_path)
    exp = load_experiment(write_config(tmp_path))
    summary = run_sweep(exp, tmp_path / "other", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert summary.references_rendered == 0 and summary.references_cached == 6


@pytest.mark.slow
def test_failing_cell_is_recorded_and_the_sweep_goes_on(tmp_path, test_methods):
    text = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged", "test-fails-on-fans"]')
    _, out, summary = _run(tmp_path, text)
    assert summary.total == 12 and summary.ran == 12
    table = pd.read_parquet(out / "results.parquet")
    bad = table[table["error"].notna()]
    # fans of 6 and 12 triangles fail; the fan of 3 and everything else succeed
    assert sorted(bad["difficulty"]) == [6, 12]
    assert all("too many polygons" in e for e in bad["error"])
    assert bad["rmse"].isna().all()
    assert table[table["error"].isna()]["rmse"].notna().all()
    # failures are results: a rerun does not repeat them unless asked
    _, _, again = _run(tmp_path, text)
    assert again.ran == 0
    _, _, retried = _run(tmp_path, text, retry_failed=True)
    assert retried.ran == 2 and retried.failed == 2


@pytest.mark.slow
def test_a_sweep_with_failed_cells_exits_3_and_names_each_error_once(tmp_path, test_methods, capsys):
    from aaeval.cli import main

    text = SMALL.replace('methods = ["catmull-jagged"]', 'methods = ["catmull-jagged", "test-fails-on-fans"]')
    config = write_config(tmp_path, text)
    argv = ["sweep", str(config), "--out", str(tmp_path / "out"), "--workers", "1", "-q", "--cache", str(tmp_path / "c")]
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert "2 cell(s) failed" in err and err.count("too many polygons") == 1, err
    assert "2 x MethodFailure: method 'test-fails-on-fans' failed: RuntimeError: too many polygons" in err, err
    assert "e.g. stability / fan@6 / test-fails-on-fans / frame 0" in err, err
    # a rerun keeps the failures as results, and still says so
    assert main(argv) == 3
    assert "2 kept from earlier runs" in capsys.readouterr().err


def test_a_cache_that_is_not_a_folder_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    from tests.helpers.cli_util import refused

    (tmp_path / "file").write_text("")
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path / "file"))
    refused(["sweep", str(write_config(tmp_path)), "--out", str(tmp_path / "out"), "--workers", "1", "-q"],
            capsys, tmp_path / "file", "not a folder")
    assert not (tmp_path / "out").exists()


def _sweep_process(config, out, cache, pause=0.25):
    """The sweep in a process of its own, one worker; each cell pauses ``pause`` s (the rerun
    needs none: it only has to finish)."""
    return slow_sweep(config, out, cache, workers=1, pause=pause, cwd=ROOT, stdout=subprocess.PIPE,
                      stderr=subprocess.STDOUT)


def _cell_files(out):
    # a kill can leave a temporary ".name" file behind: it is not a cell
    cells = out / "cells"
    return {p.name: p.read_bytes() for p in cells.glob("*.json") if not p.name.startswith(".")} if cells.is_dir() else {}


@pytest.mark.slow
def test_sigkill_loses_no_finished_cell_and_duplicates_none(tmp_path, test_methods):
    config, out, cache = write_config(tmp_path, slow_config("kill", 14)), tmp_path / "out", tmp_path / "cache"
    proc = _sweep_process(config, out, cache)
    deadline = time.monotonic() + 60
    while len(_cell_files(out)) < 3:
        assert proc.poll() is None, proc.stdout.read().decode()
        assert time.monotonic() < deadline, "no cells finished in 60 s"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    before = _cell_files(out)
    assert 3 <= len(before) < 14, "the kill must land mid-sweep"

    rerun = _sweep_process(config, out, cache, pause=0)
    output = rerun.communicate(timeout=120)[0].decode()
    assert rerun.returncode == 0, output
    assert f"{len(before)} already done" in output
    after = _cell_files(out)
    keys = {p.key for p in plan(load_experiment(config))}
    assert {name[:-5] for name in after} == keys  # every cell, each exactly once
    for name, content in before.items():  # finished cells were not recomputed
        assert after[name] == content
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 14 and table["key"].is_unique and sorted(table["frame"]) == list(range(14))
    assert table["error"].isna().all()
    pids = {json.loads(c)["pid"] for c in after.values()}
    assert len(pids) == 2  # the killed run and the rerun, nothing else


def test_cli_dry_run_lists_cells_and_what_is_done(tmp_path):
    from aaeval.cli import main

    config = write_config(tmp_path)
    out = tmp_path / "out"
    assert main(["sweep", str(config), "--out", str(out), "--dry-run"]) == 0
    assert not (out / "cells").exists()
    _run(tmp_path)
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["sweep", str(config), "--out", str(out), "--dry-run"]) == 0
    text = buf.getvalue()
    assert "9 cells" in text and "9 done" in text
    assert "catmull-jagged" in text and "frames   3/3" in text


def test_cli_reports_config_errors_in_one_line(tmp_path, capsys):
    from aaeval.cli import main

    path = write_config(tmp_path, SMALL.replace('metrics = ["rmse", "psnr"]', 'metrics = ["nope"]'))
    assert main(["sweep", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "[experiment].metrics" in err


def test_a_metric_that_cannot_judge_a_cell_spoils_no_other_metric(tmp_path):
    # SSIM needs 3 pixels a side: on a 2x2 scene it raises; rmse of the same cell stands
    (tmp_path / "tiny.toml").write_text(
        "[image]\nwidth = 2\nheight = 2\n[[polygons]]\ncolor = [1, 0, 0]\nvertices = [[0.2, 0.3, 0], [1.7, 0.4, 0], [0.9, 1.8, 0]]\n")
    text = SMALL.replace('metrics = ["rmse", "psnr"]', 'metrics = ["rmse", "ssim"]').replace(
        'scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]', 'scenes = ["tiny.toml"]')
    _, out, summary = _run(tmp_path, text)
    assert summary.failed == 0
    table = pd.read_parquet(out / "results.parquet")
    tiny = table[table["scene"] == "tiny"]
    assert len(tiny) == 2 and tiny["error"].isna().all()
    assert tiny["ssim"].isna().all() and tiny["metric_errors"].str.contains("SSIM needs").all()
    assert (tiny[tiny["method"] == "catmull-jagged"]["rmse"] > 0).all()
    assert table[table["scene"] != "tiny"]["ssim"].notna().all()


def test_a_seeded_reference_states_its_measured_noise(tmp_path):
    import math

    from aaeval.report.ground_truth_section import reference_statement

    text = SMALL.replace('reference = "catmull"', 'reference = "jitter:k=2,seed=3"')
    exp, out, _ = _run(tmp_path, text)
    table = pd.read_parquet(out / "results.parquet")
    assert (table["reference_kind"] == "stochastic").all() and (table["reference_seed"] == 3).all()
    row = table[table["scene"] == "fan@6"].iloc[0]
    scene = next(c.scene_source for c in exp.cells() if c.scene_source.name == "fan@6").parsed
    a, b = render(scene, "jitter:k=2,seed=3"), render(scene, "jitter:k=2,seed=4")
    assert row["reference_noise_rmse"] == pytest.approx(np.sqrt(np.mean((a - b) ** 2)) / math.sqrt(2), rel=1e-12)
    assert row["reference_noise_rmse"] > 0
    refs = pd.read_parquet(out / "summaries" / "references.parquet")
    statement = reference_statement(refs[refs["group"] == "stability"])
    assert "jitter:k=2,seed=3" in statement and "stochastic" in statement and "noise RMS" in statement


def test_a_failing_reference_fails_its_cells_only(tmp_path, test_methods):
    text = SMALL.replace('name = "stability"', 'name = "stability"\nreference = "test-fails-on-fans"')
    _, out, summary = _run(tmp_path, text)
    assert summary.ran == 9 and summary.failed == 2 and not summary.lost
    table = pd.read_parquet(out / "results.parquet")
    bad = table[table["error"].notna()]
    assert sorted(bad["difficulty"]) == [6, 12]
    assert all("reference test-fails-on-fans failed" in e and "too many polygons" in e for e in bad["error"])
