"""A small sweep and its report, shared by the report tests (built once per test session):
a Mitsuba ground truth for two groups (one animated, one with difficulty levels) and an
exact reference for a third, so the page shows both policies."""

from __future__ import annotations

from pathlib import Path

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.report import write_report

REPORT_CONFIG = """
[experiment]
name = "small"
description = "test sweep"
reference = "mitsuba:sampler=stratified,spp=256,seed=0"
metrics = ["rmse", "psnr", "flip"]
temporal = ["sum_variation", "flicker"]
fail_above = 0.1

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]
methods = ["catmull", "catmull-jagged", "supersample"]
options.supersample = { k = [2, 4] }

[[groups]]
name = "stability"
scenes = [{generator = "fan", difficulty = [3, 6, 12], size = 5}]
methods = ["catmull", "catmull-jagged"]

[[groups]]
name = "exact reference"
reference = "catmull"
scenes = [{generator = "fan", difficulty = [6], size = 6}]
methods = ["weiler-atherton", "catmull-jagged"]
"""
CELLS = 3 * 4 + 3 * 2 + 2  # edges: 3 frames x 4 specs; stability: 3 scenes x 2; exact reference: 2

_BUILT: dict[str, Path] = {}


def small_report(tmp_path_factory) -> Path:
    """``index.html`` of the small sweep (built on first use in this session)."""
    if "index" not in _BUILT:
        tmp = tmp_path_factory.mktemp("report")
        config = tmp / "exp.toml"
        config.write_text(REPORT_CONFIG)
        out = tmp / "sweep"
        run_sweep(load_experiment(config), out, workers=1, quiet=True, cache_dir=tmp / "cache")
        _BUILT["index"] = write_report(out)  # as 'aaeval report' writes it: the paper formats are tested on it
    return _BUILT["index"]
