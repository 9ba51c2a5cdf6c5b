"""Small experiment configs for the sweep and report tests (generated scenes: no files)."""

from __future__ import annotations

from pathlib import Path

SMALL = """
[experiment]
name = "small"
description = "test sweep"
reference = "catmull"
metrics = ["rmse", "psnr"]
temporal = ["sum_variation", "flicker"]
fail_above = 0.1

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]
methods = ["catmull", "catmull-jagged"]

[[groups]]
name = "stability"
scenes = [{generator = "fan", difficulty = [3, 6, 12], size = 5}]
methods = ["catmull-jagged"]
"""


def write_config(tmp_path: Path, text: str = SMALL, name: str = "exp.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path
