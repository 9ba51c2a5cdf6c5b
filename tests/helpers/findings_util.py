"""A small sweep with every kind of group the findings read (edges, specular, filters, a speed
pass) and its report, built once per test session."""

from __future__ import annotations

from pathlib import Path

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.report import write_report

CONFIG = """
[experiment]
name = "findings"
reference = "mitsuba:sampler=stratified,spp=64,seed=0"
metrics = ["rmse", "edge_rmse"]
temporal = ["sum_variation", "temporal_bias", "flicker"]
fail_above = 0.05

[[groups]]
name = "edge-aliasing"
scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]
methods = ["catmull", "point", "supersample"]
options.supersample = { k = [2, 4] }

[[groups]]
name = "specular"
reference = "mitsuba:spp=64,seed=0"
metrics = ["rmse", "highlight_rmse"]
temporal = ["temporal_bias", "flicker", "highlight_bias", "highlight_profile_flicker"]
scenes = [{generator = "shininess", difficulty = [500], size = 16, frames = 3}]
methods = ["catmull"]
options.catmull = { specular = ["none", "amanatides", "toksvig"] }

[[groups]]
name = "filters"
metrics = ["rmse"]
temporal = ["temporal_bias", "flicker", "image_flicker"]
scenes = [{generator = "edges", difficulty = [0.05], size = 12, frames = 3}]
methods = ["catmull", "supersample"]
[groups.options]
filter = ["box", "tent"]
supersample = { k = [2] }

[[speed]]
accuracy = "edge-aliasing"
scenes = [{generator = "random", difficulty = [20], size = 256}]
methods = ["catmull", "point", "skia", "supersample"]
options.supersample = { k = [2, 4] }
repeats = 2
"""

_BUILT: dict[str, Path] = {}


def findings_report(tmp_path_factory) -> Path:
    """The sweep folder (with ``index.html``), built on first use in this session."""
    if "out" not in _BUILT:
        tmp = tmp_path_factory.mktemp("findings")
        config = tmp / "exp.toml"
        config.write_text(CONFIG)
        out = tmp / "sweep"
        run_sweep(load_experiment(config), out, workers=1, quiet=True, cache_dir=tmp / "cache")
        # PNG (the page) and SVG (which the findings tests read); the PDF twins, a third of
        # the report's time in font subsetting, are tested on the small report
        write_report(out, formats=("png", "svg"))
        _BUILT["out"] = out
    return _BUILT["out"]
