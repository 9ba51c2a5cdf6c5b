"""The path from a scene to a number in the results table: one engine, one record, one row
per cell, and aggregations checked against independent recomputations."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore, load_experiment, run_sweep
from aaeval.sweeps.config import parse_experiment
from aaeval.sweeps.config_keys import ConfigError
from aaeval.sweeps.record import SCHEMA_VERSION, TIMING_FIELDS, CellRecord, RecordError
from aaeval.sweeps.table import read_table
from aaeval.metrics import METRICS, register_metric
from tests.helpers.sweep_util import MOVING, moving_config, run_moving_sweep, strict_json, write_config

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("group, message", [
    ('scenes = [{generator = "fan", difficulty = [3, 3]}]\nmethods = ["catmull"]', "given more than once"),
    ('scenes = ["../../configs/scenes/abutting.toml", "../../configs/scenes/abutting.toml"]\nmethods = ["catmull"]',
     "listed twice"),
    ('scenes = [{generator = "fan", difficulty = [3]}]\nmethods = ["catmull", "catmull"]', "already in this group"),
    ('scenes = [{generator = "fan", difficulty = [3]}]\nmethods = ["supersample", "supersample:k=4"]\n'
     'options.supersample = { k = [2, 4] }', "already in this group"),
    ('scenes = [{generator = "edges", difficulty = [0.1]}]\nmethods = ["catmull"]\nframes = [1, 1]',
     "given more than once"),
    ('scenes = [{generator = "fan", difficulty = [3]}]\nmethods = ["catmull"]\nrepeats = 0', "repeats"),
])
def test_a_config_that_repeats_itself_is_refused_naming_the_key(group, message):
    import tomllib

    text = f'[experiment]\nreference = "catmull"\n\n[[groups]]\nname = "g"\n{group}\n'
    path = ROOT / "tests" / "data" / "x.toml"  # scene paths resolve from here
    with pytest.raises(ConfigError, match=message) as info:
        parse_experiment(tomllib.loads(text), path=path, text=text)
    assert "groups[0]" in str(info.value)


# --- one record ------------------------------------------------------------------------

def test_a_record_with_a_missing_or_unknown_field_or_another_schema_is_refused():
    from aaeval.sweeps.record import _INT, _STR

    fields = {f: None for f in CellRecord.__dataclass_fields__}  # every optional field null
    fields.update({f: "x" for f in _STR}, **{f: 1 for f in _INT})  # the others of their types
    fields.update(metrics={}, metric_errors={}, options={}, schema_version=SCHEMA_VERSION)
    CellRecord.from_json(fields)
    with pytest.raises(RecordError, match="field 'frame' must be a whole number"):
        CellRecord.from_json({**fields, "frame": "0"})
    with pytest.raises(RecordError, match=r"missing \['render_s'\]"):
        CellRecord.from_json({k: v for k, v in fields.items() if k != "render_s"})
    with pytest.raises(RecordError, match=r"unknown \['rmse_typo'\]"):
        CellRecord.from_json({**fields, "rmse_typo": 1.0})
    with pytest.raises(RecordError, match="schema version 1"):
        CellRecord.from_json({**fields, "schema_version": 1})


@pytest.fixture(scope="module")
def moving_sweep(tmp_path_factory):
    return run_moving_sweep(tmp_path_factory.mktemp("moving"))


@pytest.mark.slow
def test_cell_files_are_strict_json_records_with_timings_and_the_table_carries_the_schema(moving_sweep):
    out = moving_sweep / "out"
    for path in (out / "cells").glob("*.json"):
        record = CellRecord.from_json(strict_json(path.read_text()))
        assert record.repeats == 3 and record.render_s_min <= record.render_s <= record.render_s_max
        assert record.megapixels == 14 * 10 / 1e6
        assert record.ms_per_mpix == pytest.approx(record.render_s * 1e3 / record.megapixels)
    table = read_table(out / "results.parquet")
    assert set(TIMING_FIELDS) <= set(table.columns)
    provenance = strict_json((out / "provenance.json").read_text())
    assert provenance["cores"] >= 1 and provenance["workers"] == 1 and provenance["versions"]["numpy"]
    assert provenance["cpu_model"] and provenance["machine"]


def test_compare_and_a_sweep_give_identical_numbers(moving_sweep, capsys):
    out = moving_sweep / "out"
    results = pd.read_parquet(out / "results.parquet")
    temporal = pd.read_parquet(out / "temporal.parquet").set_index("spec")
    assert main(["compare", str(moving_sweep / "moving.toml"), "-m", "catmull-jagged", "-m", "supersample:k=3",
                 "-r", "catmull", "--frames", "all", "--metric", "rmse", "--metric", "ssim", "--metric",
                 "edge_rmse", "--temporal", "sum_variation", "--temporal", "flicker", "--format", "json"]) == 0
    doc = strict_json(capsys.readouterr().out)
    for row in doc["rows"]:
        cell = results[(results["spec"] == row["method"]) & (results["frame"] == row["frame"])]
        assert len(cell) == 1
        for name in ("rmse", "ssim", "edge_rmse", "intensity_sum"):
            assert row[name] == cell[name].iloc[0], (row["method"], row["frame"], name)
    for entry in doc["summary"]:
        for name in ("sum_variation", "flicker"):
            assert entry["temporal"][name] == temporal.loc[entry["method"], name]


# --- one registration ------------------------------------------------------------------

def _toy(image_true, image_test) -> float:
    """Mean absolute difference (a toy metric for the registry test)."""
    return float(np.mean(np.abs(np.asarray(image_test) - np.asarray(image_true))))


@pytest.fixture
def toy_metric():
    register_metric("toy_mad", _toy, kind="image", title="TOY MAD", fmt=".5f")
    yield
    METRICS.unregister("toy_mad")


@pytest.mark.slow
def test_a_metric_registered_once_shows_in_compare_sweep_and_report(toy_metric, tmp_path, capsys):
    from aaeval.report import write_report

    (tmp_path / "moving.toml").write_text(MOVING)
    assert main(["compare", str(tmp_path / "moving.toml"), "-m", "catmull-jagged", "-r", "catmull"]) == 0
    printed = capsys.readouterr().out
    assert "TOY MAD" in printed
    assert main(["compare", str(tmp_path / "moving.toml"), "-m", "catmull-jagged", "-r", "catmull",
                 "--format", "json"]) == 0
    doc = strict_json(capsys.readouterr().out)
    assert doc["rows"][0]["toy_mad"] > 0
    exp = load_experiment(moving_config(tmp_path, metrics='["rmse", "toy_mad"]', temporal="[]"))
    run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    table = pd.read_parquet(tmp_path / "out" / "results.parquet")
    assert (table["toy_mad"] > 0).all()
    html = write_report(tmp_path / "out", formats=("png",)).read_text()  # only the page is read
    assert "toy_mad" in html or "TOY MAD" in html
    assert main(["metrics"]) == 0
    assert "toy_mad" in capsys.readouterr().out


def test_registry_refuses_a_bad_registration():
    from aaeval.metrics import MetricError

    with pytest.raises(MetricError, match="registered twice"):
        register_metric("rmse", _toy, kind="image", title="x", fmt=".3f")
    with pytest.raises(MetricError, match="unknown mask"):
        register_metric("toy_masked", _toy, kind="image", title="x", fmt=".3f", mask="nowhere")
    with pytest.raises(MetricError, match="takes no 'mask'"):
        register_metric("toy_masked", _toy, kind="image", title="x", fmt=".3f", mask="edge")
    with pytest.raises(MetricError, match="bad number format"):
        register_metric("toy_fmt", _toy, kind="image", title="x", fmt="%d")
    assert "toy_masked" not in METRICS and "toy_fmt" not in METRICS


# --- highlight metrics are sweep metrics ------------------------------------------------

SHINY = """
[experiment]
name = "shiny"
reference = "catmull:specular=crow,k=8,region=all"
metrics = ["rmse", "highlight_rmse", "highlight_energy_bias"]
temporal = ["highlight_flicker", "highlight_energy_flicker"]

[[groups]]
name = "shiny"
scenes = [{generator = "shininess", difficulty = [200], size = 16, frames = 3}]
methods = ["catmull:specular=none", "catmull:specular=amanatides"]
"""


@pytest.mark.slow
def test_highlight_metrics_run_in_a_sweep_over_the_ground_truth_highlight(tmp_path):
    from aaeval.metrics.masks import HIGHLIGHT_SPP, HIGHLIGHT_THRESHOLD
    from aaeval.groundtruth import groundtruth_phong

    exp = load_experiment(write_config(tmp_path, SHINY))
    run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    store = SweepStore(tmp_path / "out")
    results = pd.read_parquet(tmp_path / "out" / "results.parquet")
    temporal = pd.read_parquet(tmp_path / "out" / "temporal.parquet")
    assert results["error"].isna().all() and len(results) == 6 and len(temporal) == 2
    scene = exp.groups[0].scenes[0].parsed
    masks, tests, refs = [], [], []
    for _, cell in results[results["spec"] == "catmull"].sort_values("frame").iterrows():
        _, specular, _ = groundtruth_phong(scene.at_frame(int(cell["frame"])), spp=HIGHLIGHT_SPP)
        mask = specular > HIGHLIGHT_THRESHOLD
        assert mask.any()
        test, ref = np.load(store.image_path(cell["key"])), np.load(store.reference_path(cell["reference_key"]))
        expected = math.sqrt(float(np.mean((test[mask] - ref[mask]) ** 2)))
        assert cell["highlight_rmse"] == pytest.approx(expected, rel=1e-12)
        masks.append(mask), tests.append(test), refs.append(ref)
    still = np.any(masks, axis=0)
    change = np.diff(np.stack(tests) - np.stack(refs), axis=0)[:, still]
    row = temporal.set_index("spec").loc["catmull"]
    assert row["highlight_flicker"] == pytest.approx(math.sqrt(float(np.mean(change**2))), rel=1e-12)
