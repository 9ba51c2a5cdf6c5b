"""``aaeval compare`` end to end, and the comparison library under it."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from aaeval.cli import main
from aaeval.sweeps.compare import parse_frames, plan_comparison, run_comparison
from aaeval.sweeps.record import TIMING_FIELDS
from aaeval.metrics import METRICS
from aaeval.renderers import MethodError, render
from aaeval.scenes import SceneError
from tests.helpers.oracle import document_oracle_image, document_visible_areas
from tests.helpers.sweep_util import strict_json

TINY = (Path(__file__).resolve().parents[1] / "data" / "scenes" / "two_triangles_16x12.toml").read_text()


# every image metric that applies to a flat scene (highlight metrics need [shaded] objects)
FLAT_METRICS = [n for n, m in METRICS.items() if m.kind == "image" and m.mask != "highlight"]


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    return path


def compare(*args) -> int:
    return main(["compare", *map(str, args)])


def test_compare_writes_rows_and_temporal_summaries(scene_file, tmp_path, capsys):
    out = tmp_path / "out" / "compare.json"
    assert compare(scene_file, "-m", "catmull", "-m", "catmull-jagged", "-r", "catmull",
                   "--frames", "all", "--json", out) == 0
    printed = capsys.readouterr().out
    assert "catmull-jagged" in printed and "sum var" in printed
    assert max(len(line) for line in printed.splitlines()) <= 100
    doc = json.loads(out.read_text())
    assert doc["frames"] == [0, 1, 2, 3] and doc["reference"] == "catmull"
    assert doc["metrics"] == FLAT_METRICS
    assert [(r["method"], r["frame"]) for r in doc["rows"]] == [
        (m, k) for k in range(4) for m in ("catmull", "catmull-jagged")
    ]
    for row in doc["rows"]:
        assert set(row) == {"method", "frame", *FLAT_METRICS, "intensity_sum", *TIMING_FIELDS, "error",
                            "metric_errors", "failure"}
        assert row["render_s"] > 0 and row["repeats"] == 1 and row["megapixels"] == 16 * 12 / 1e6
        assert row["render_s_min"] <= row["render_s"] <= row["render_s_max"]
        assert row["ms_per_mpix"] == pytest.approx(row["render_s"] * 1e3 / row["megapixels"])
        if row["method"] == "catmull":  # the exact method against itself
            assert row["rmse"] == 0 and row["psnr"] == "Infinity" and row["ssim"] == 1  # PSNR inf, kept as such
            assert row["ciede2000_mean"] == row["ciede2000_p95"] == row["flip"] == row["edge_rmse"] == 0
        else:
            assert row["rmse"] > 0.01 and row["edge_rmse"] > row["rmse"] and row["psnr"] < 40

    summary = {s["method"]: s for s in doc["summary"]}
    reference_variation = doc["reference_summary"]["sum_variation"]
    # area sampling keeps the sum under sub-pixel motion; the jagged mode does not
    assert reference_variation < 1e-12
    assert summary["catmull"]["temporal"]["sum_variation"] == reference_variation
    assert summary["catmull"]["temporal"]["flicker"] == 0
    assert summary["catmull-jagged"]["temporal"]["sum_variation"] > 1e-3
    assert summary["catmull-jagged"]["temporal"]["flicker"] > 1e-3
    for entry in summary.values():
        assert entry["reference_sum_variation"] == reference_variation and entry["frames"] == 4
        assert set(entry["mean"]) == set(FLAT_METRICS)
    jagged_rmse = [r["rmse"] for r in doc["rows"] if r["method"] == "catmull-jagged"]
    assert summary["catmull-jagged"]["mean"]["rmse"] == pytest.approx(sum(jagged_rmse) / 4, rel=1e-12)


def test_rows_hold_the_metrics_of_the_rendered_frames(scene_file):
    plan = plan_comparison(str(scene_file), ["catmull-jagged"], "catmull", frames=2, metrics=["rmse", "edge_rmse"])
    doc = run_comparison(plan)
    scene = plan.scene
    truth, test = render(scene, "catmull", frame=1), render(scene, "catmull-jagged", frame=1)
    row = doc["rows"][1]
    assert row["frame"] == 1 and set(row) == {"method", "frame", "rmse", "edge_rmse", "intensity_sum",
                                              *TIMING_FIELDS, "error", "metric_errors", "failure"}
    # expected values by another route: GEOS on the raw document for the exact image and
    # for the pixels an edge crosses (no pixel wholly one polygon's or the background's),
    # and the RMSE written out
    document = tomllib.loads(TINY)
    exact = document_oracle_image(document, frame=1)
    assert np.abs(truth - exact).max() < 1e-12
    mask = document_visible_areas(document, frame=1).max(axis=2) < 1.0 - 1e-9
    assert 0 < mask.sum() < mask.size
    diff = test - exact
    assert row["rmse"] == pytest.approx(math.sqrt((diff**2).sum() / diff.size), rel=1e-9)
    assert row["edge_rmse"] == pytest.approx(math.sqrt((diff[mask] ** 2).sum() / (3 * mask.sum())), rel=1e-9)
    assert row["intensity_sum"] == pytest.approx(test.sum(), rel=1e-12)


def test_default_is_one_frame_and_quiet_prints_only_the_summary(scene_file, tmp_path, capsys):
    out = tmp_path / "one.json"
    assert compare(scene_file, "-m", "catmull-jagged", "-r", "catmull", "--json", out, "--quiet") == 0
    printed = capsys.readouterr().out
    assert "median ms" in printed and "against catmull" not in printed and "wrote" not in printed
    doc = json.loads(out.read_text())
    assert doc["frames"] == [0] and len(doc["rows"]) == 1


@pytest.mark.parametrize(
    "args, message",
    [
        (["-m", "nope", "-r", "catmull"], "unknown method 'nope'"),
        (["-m", "catmull", "-r", "catmull:bogus=2"], "unknown option"),
        (["-m", "catmull", "-m", "catmull:", "-r", "catmull"], "give each method once"),
        (["-m", "catmull", "-r", "catmull", "--frames", "5"], "only 4 frame"),
        (["-m", "catmull", "-r", "catmull", "--frames", "0"], "at least 1"),
        (["-m", "catmull", "-r", "catmull", "--frames", "some"], "positive number or 'all'"),
        (["-m", "catmull", "-r", "catmull", "--metric", "rmsee"], "unknown image metric(s) ['rmsee']"),
        (["-m", "catmull", "-r", "catmull", "--temporal", "rmse"], "unknown temporal metric(s) ['rmse']"),
        (["-m", "catmull", "-r", "catmull", "--repeats", "0"], "--repeats must be"),
    ],
)
def test_bad_input_fails_in_one_line_and_keeps_the_old_output(scene_file, tmp_path, capsys, args, message):
    out = tmp_path / "kept.json"
    out.write_text("earlier results\n")
    assert compare(scene_file, *args, "--json", out) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert out.read_text() == "earlier results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.json", "tiny.toml"]


def test_bad_scene_fails_before_rendering(tmp_path, capsys):
    broken = tmp_path / "broken.toml"
    broken.write_text("[image]\nwidth = 0\nheight = 4\n")
    out = tmp_path / "never.json"
    assert compare(broken, "-m", "catmull", "-r", "catmull", "--json", out) == 2
    assert "broken.toml" in capsys.readouterr().err
    assert not out.exists()
    with pytest.raises(SceneError):
        plan_comparison(str(tmp_path / "missing.toml"), ["catmull"], "catmull")


def test_planning_checks_specs_before_the_scene():
    with pytest.raises(MethodError):
        plan_comparison("/nonexistent.toml", ["catmull"], "nope")
    with pytest.raises(ValueError, match="at least one"):
        plan_comparison("/nonexistent.toml", [], "catmull")


def test_parse_frames():
    assert parse_frames("all", 3) == (0, 1, 2)
    assert parse_frames("2", 3) == (0, 1)
    assert parse_frames(1, 1) == (0,)


LONG = ["catmull", "catmull-jagged", "mitsuba:sampler=stratified,seed=1,spp=4", "supersample:k=3"]


def test_every_format_holds_every_metric_and_the_table_fits_100_columns(scene_file, tmp_path, capsys):
    args = [scene_file, *(a for m in LONG for a in ("-m", m)), "-r", "catmull", "--frames", "2", "-q"]
    assert compare(*args, "--format", "table") == 0
    table = capsys.readouterr().out
    assert max(len(line) for line in table.splitlines()) <= 100
    for name in FLAT_METRICS:
        assert METRICS[name].title in table
    assert compare(*args, "--format", "json", "--json", tmp_path / "c.json") == 0
    doc = strict_json(capsys.readouterr().out)
    assert doc == strict_json((tmp_path / "c.json").read_text())
    exact = next(r for r in doc["rows"] if r["method"] == "catmull")
    assert exact["psnr"] == "Infinity"  # strict JSON has no inf: its tag
    assert compare(*args, "--format", "csv") == 0
    import csv
    import io

    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert len(rows) == len(doc["rows"]) == 2 * len(LONG)
    for row, ref in zip(rows, doc["rows"]):
        assert row["method"] == ref["method"] and float(row["rmse"]) == ref["rmse"]
    assert compare(*args, "--format", "markdown") == 0
    md = capsys.readouterr().out
    assert md.count("| catmull-jagged |") == 3  # two frames and the summary
