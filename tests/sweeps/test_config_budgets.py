"""Configs budgeted before any work: a million-frame list, a 1e5-step
difficulty ladder, more cells than a config may plan and a speed pass no run would finish are
refused at parse time in one line (exit 2) with their count or estimate; error lines stay
readable; the memory estimate honours RLIMIT_AS."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.helpers.cli_util import refused

ROOT = Path(__file__).resolve().parents[2]

HEAD = """
[experiment]
name = "budget"
reference = "catmull"
metrics = ["rmse"]
temporal = []
"""


def config_refused(capsys, config: Path, *words: str, within: float = 30) -> str:
    """``aaeval sweep --dry-run`` refuses ``config`` in one short line within ``within`` s."""
    start = time.monotonic()
    out = config.parent / "out"
    err = refused(["sweep", config, "--out", out, "--dry-run"], capsys, *words, written=[out])
    assert time.monotonic() - start < within
    assert len(err) < 1200, len(err)
    return err


def _frame_list(config: Path, frames) -> Path:
    """A config of one 100,000-frame scene (the most a scene may have) and this frame list."""
    config.write_text(HEAD + f"""
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = [0.1], frames = 100000, size = 8}}]
methods = ["point"]
frames = [{", ".join(map(str, frames))}]
""")
    return config


@pytest.mark.slow
def test_a_million_frame_list_is_refused_within_30_s(tmp_path, capsys):
    config = _frame_list(tmp_path / "frames.toml", range(1_000_000))
    config_refused(capsys, config, "1000000 frame numbers", "100000")


def test_repeated_and_outside_frames_are_found_by_counting_once(tmp_path, capsys):
    """60k frames took 50 s with list.count per item; the refusal shows a few, not all."""
    config = _frame_list(tmp_path / "twice.toml", list(range(50_000)) * 2)
    config_refused(capsys, config, "given more than once", "50000 in all", within=20)


def test_a_long_ladder_is_refused_with_its_estimate(tmp_path, capsys):
    levels = ", ".join(str(i * 1e-6) for i in range(1, 100_001))
    config = tmp_path / "ladder.toml"
    config.write_text(HEAD + f"""
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = [{levels}], size = 8}}]
methods = ["point"]
""")
    config_refused(capsys, config, "100000 steps", "limit of 1000", within=20)


def test_too_many_cells_are_refused_before_any_is_built(tmp_path, capsys):
    from aaeval.sweeps.config_budgets import MAX_CELLS

    methods = ", ".join(f'"supersample:k={k}"' for k in range(1, 4))
    config = tmp_path / "cells.toml"
    config.write_text(HEAD + f"""
[[groups]]
name = "g"
scenes = [{{generator = "edges", difficulty = [0.1], frames = 100000, size = 4}}]
methods = [{methods}]
""")
    config_refused(capsys, config, "300000 cells", str(MAX_CELLS), "hours")


def test_a_speed_pass_no_run_would_finish_is_refused_with_the_estimate(tmp_path, capsys):
    config = tmp_path / "speed.toml"
    config.write_text(HEAD.replace('temporal = []', 'temporal = []\nmax_seconds = 1') + """
[[groups]]
name = "g"
scenes = [{generator = "edges", difficulty = [0.1], size = 8}]
methods = ["point"]

[[speed]]
scenes = [{generator = "edges", difficulty = [0.1], size = 2048, frames = 1}]
methods = ["supersample:k=8"]
repeats = 1000
""")
    config_refused(capsys, config, "speed[0]", "would take about", "limit of 1 s")


def test_error_lines_are_cut_to_a_readable_length(capsys):
    from aaeval.cli import MAX_ERROR_CHARS, _one_line

    line = _one_line("x" * 10_000_000)
    assert len(line) < MAX_ERROR_CHARS + 100 and "characters cut" in line


def test_the_memory_estimate_honours_rlimit_as():
    code = """
import resource
from aaeval.limits import available_memory
soft = 3 << 30
resource.setrlimit(resource.RLIMIT_AS, (soft, resource.getrlimit(resource.RLIMIT_AS)[1]))
print(available_memory() <= soft)
"""
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.stdout.strip() == "True", done.stderr
