"""The results tables (:mod:`aaeval.sweeps.table`): one row per cell with its own label,
aggregations over frames checked against recomputations written here, and tables that heal
a damaged cell instead of failing."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from aaeval.sweeps import SweepStore, load_experiment, plan, run_sweep
from aaeval.sweeps.record import CellRecord
from aaeval.sweeps.runner import manifest, record_identity
from aaeval.sweeps.table import results_frame, short_label, write_results
from tests.helpers.sweep_util import first_file, quarantined, run_moving_sweep, run_small_sweep, write_config

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "configs" / "sweeps").glob("*.toml"))


@pytest.fixture(scope="module")
def moving_sweep(tmp_path_factory):
    return run_moving_sweep(tmp_path_factory.mktemp("moving"))


# --- one row per cell ------------------------------------------------------------------

def _fake_record(p, ref_meta=None) -> dict:
    """A record for a planned cell without rendering (what the table does with it is tested)."""
    measured = {"repeats": 1, "render_s": 1e-3, "render_s_min": 1e-3, "render_s_max": 1e-3, "megapixels": 1.0,
                "ms_per_mpix": 1.0, "intensity_sum": 1.0, "metrics": {m: 0.5 for m in p.cell.metrics},
                "metric_errors": {}, "error": None, "traceback": None}
    run = {"host": "h", "pid": 1, "executor": "this process", "workers": 1, "finished_at": "now"}
    return CellRecord(**record_identity(p, ref_meta or {}), **measured, **run).to_json()


@pytest.mark.slow
@pytest.mark.parametrize("config", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_every_cell_of_every_shipped_config_is_one_row_with_its_own_label(config, memory_tmp_path):
    experiment = load_experiment(config)
    planned = plan(experiment)
    keys = [p.key for p in planned]
    assert len(keys) == len(set(keys)), "two cells share a key"
    store = SweepStore(memory_tmp_path)  # thousands of cells, each an image and a record
    store.write_manifest(experiment.text, manifest(experiment, planned))
    written, cells = set(), []
    for p in planned:  # the store checks that every finished cell has its image and reference, of its size
        blank = np.zeros((p.cell.scene_source.parsed.height, p.cell.scene_source.parsed.width, 3))
        if p.reference_key not in written:  # one reference serves every method of a scene frame
            store.write_reference(p.reference_key, blank)
            written.add(p.reference_key)
        cells.append((_fake_record(p), blank, None))
    store.write_cells(cells)  # one batch, its syncs shared, as a sweep writes the cells it has finished
    table = results_frame(store)
    assert len(table) == len(planned) == len(store.read_manifest()["cells"])
    assert not table["key"].duplicated().any()
    # every (group, scene, difficulty, spec, frame) of the config is there exactly once
    wanted = sorted((c.group, c.scene_source.name, c.scene_source.difficulty, c.spec, c.frame) for c in experiment.cells())
    got = sorted(zip(table["group"], table["scene"], [None if math.isnan(d) else d for d in table["difficulty"]],
                     table["spec"], table["frame"]))
    assert got == wanted
    # every difficulty listed in the config appears with its own label
    raw = experiment.text and __import__("tomllib").loads(experiment.text)
    for g in raw["groups"]:
        for entry in g["scenes"]:
            if isinstance(entry, dict) and "generator" in entry:
                rows = table[table["group"] == g["name"]]
                for d in entry["difficulty"]:
                    mine = rows[rows["difficulty"] == float(d)]
                    assert len(mine) > 0, (g["name"], d)
                    assert set(mine["scene"]) == {f"{entry['generator']}@{d:g}"}


@pytest.mark.slow
def test_two_difficulties_that_build_one_scene_stay_two_rows(tmp_path):
    # the curvature generator clamps the radius to 0.4 * size: at size 24, 1/0.05 and 1/0.1 both give 9.6
    text = """
[experiment]
name = "clamped"
reference = "catmull"
metrics = ["rmse"]

[[groups]]
name = "curv"
scenes = [{generator = "curvature", difficulty = [0.05, 0.1], size = 24}]
methods = ["catmull-jagged"]
"""
    exp = load_experiment(write_config(tmp_path, text))
    a, b = exp.groups[0].scenes
    assert a.digest == b.digest  # the same scene twice: what made the old table lose a row
    summary = run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert summary.total == 2 and summary.ran == 2
    table = pd.read_parquet(tmp_path / "out" / "results.parquet")
    assert sorted(table["difficulty"]) == [0.05, 0.1]
    assert sorted(table["scene"]) == ["curvature@0.05", "curvature@0.1"]
    assert table["key"].is_unique
    assert table["rmse"].iloc[0] == table["rmse"].iloc[1]


# --- over frames -----------------------------------------------------------------------

def test_every_temporal_metric_equals_a_recomputation_over_all_stored_frames(moving_sweep):
    out = moving_sweep / "out"
    store = SweepStore(out)
    results = pd.read_parquet(out / "results.parquet")
    temporal = pd.read_parquet(out / "temporal.parquet")
    assert len(temporal) == 2
    for _, row in temporal.iterrows():
        cells = results[results["spec"] == row["spec"]].sort_values("frame")
        assert list(cells["frame"]) == [0, 1, 2, 3] and row["frames"] == 4
        tests = np.stack([np.load(store.image_path(k)) for k in cells["key"]])
        refs = np.stack([np.load(store.reference_path(k)) for k in cells["reference_key"]])
        # written out here, not through aaeval.metrics
        error = tests - refs
        flicker = math.sqrt(float(np.mean(np.var(error, axis=0))))
        sums = tests.reshape(4, -1).sum(axis=1)
        ref_sums = refs.reshape(4, -1).sum(axis=1)
        assert row["flicker"] == pytest.approx(flicker, rel=1e-9)
        assert row["sum_variation"] == pytest.approx((sums.max() - sums.min()) / sums.mean(), rel=1e-9)
        assert row["reference_sum_variation"] == pytest.approx(
            (ref_sums.max() - ref_sums.min()) / ref_sums.mean(), rel=1e-6, abs=1e-15)
        # the last frame matters: without it the numbers differ
        assert row["flicker"] != pytest.approx(math.sqrt(float(np.mean(np.var(error[:-1], axis=0)))), rel=1e-6)


# --- healing ---------------------------------------------------------------------------

def test_report_tables_heal_a_damaged_cell_instead_of_failing(tmp_path, capsys):
    run_small_sweep(tmp_path)
    out = tmp_path / "out"
    victim = first_file(out / "cells")
    victim.write_text("")
    results = write_results(SweepStore(out))
    assert len(results) == 8  # the damaged cell is pending, not an error for the whole folder
    assert str(victim) in capsys.readouterr().err
    assert victim.name in quarantined(out)


# --- labels ----------------------------------------------------------------------------

def test_labels_show_options_that_vary_even_at_their_default():
    assert short_label("supersample") == "supersample"
    assert short_label("supersample", {"k"}) == "supersample:k=4"
    assert short_label("mitsuba:spp=64,cache=false,seed=1") == "mitsuba:seed=1,spp=64"
