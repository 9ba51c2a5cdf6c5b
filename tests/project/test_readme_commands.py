"""Docs that run: every shell line of the ``sh`` code blocks of the README and of
the pages it sends a developer to (docs/development.md, docs/performance.md: the inner test
loop, the benchmarks) is run, as written, in a temporary folder, and must exit 0.

The folder holds what the lines name: ``configs/scenes`` (the shipped scenes),
``scripts/quickstart.sh`` and ``benchmarks/`` (copies: their outputs land here, never in the
repository), and ``configs/sweeps/default.toml`` replaced by a small experiment of the
same shape (groups and a speed pass), so that ``bash scripts/quickstart.sh`` and the README's
``aaeval sweep``/``aaeval report`` lines run the whole path in seconds, not the default
experiment's half hour. ``python3 -m pytest`` runs as collection only (``--collect-only``, plain asserts)
of one small module with slow and quick tests (:data:`COLLECTED`): the suite cannot run itself
inside itself, and the suite's own run already imports every test module, so what the line adds
is that its command and options parse and select tests. The benchmark lines run with
``AAEVAL_BENCH_SMOKE=1`` (``benchmarks/smoke.py``: smallest sizes, one repeat), so each
takes seconds instead of minutes. The whole module is in the slow lane.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

SMALL_DEFAULT = """
[experiment]
name = "default"
description = "the README test's small stand-in for the default experiment"
reference = "mitsuba:sampler=stratified,spp=16,seed=0"
metrics = ["rmse", "edge_rmse"]
temporal = ["sum_variation", "temporal_bias", "flicker"]
fail_above = 0.05

[[groups]]
name = "edge-aliasing"
scenes = [{generator = "edges", difficulty = [0.1], frames = 2, size = 10}]
methods = ["point", "catmull"]

[[speed]]
accuracy = "edge-aliasing"
scenes = [{generator = "random", difficulty = [10], size = 256}]
methods = ["point", "skia", "catmull"]
repeats = 2
"""


# every command on one worker (pyproject's --dist loadgroup), in the README's order: one
# workspace, and the README's 'aaeval sweep'/'aaeval report' lines find what the quickstart
# wrote, as they do for a reader (a second worker would build its own and sweep again)
# slow: the README's commands run in order in one workspace (about 40 s)
pytestmark = [pytest.mark.xdist_group("readme"), pytest.mark.slow]


def readme_commands(text: str) -> list[str]:
    """Every command of the ``sh`` code blocks: comments dropped, ``\\`` continuations joined."""
    commands = []
    for block in re.findall(r"^```(?:sh|bash|shell)\n(.*?)^```", text, flags=re.S | re.M):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = re.sub(r"\s+#.*$", "", line).strip()
            if line and not line.startswith("#"):
                commands.append(line)
    return commands


PAGES = ("README.md", "docs/development.md", "docs/performance.md")
COMMANDS = [c for page in PAGES for c in readme_commands((ROOT / page).read_text())]


def test_the_readme_has_the_commands_this_test_runs():
    assert any(c.startswith("bash scripts/quickstart.sh") for c in COMMANDS)
    assert any(c.startswith("aaeval sweep") for c in COMMANDS)
    assert any("benchmarks/" in c for c in COMMANDS)
    assert all("--frame 3" not in c or "fan.toml" not in c for c in COMMANDS)  # fan.toml has one frame


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("readme")
    (tmp / "configs" / "sweeps").mkdir(parents=True)
    (tmp / "configs" / "scenes").symlink_to(ROOT / "configs" / "scenes")
    (tmp / "configs" / "sweeps" / "default.toml").write_text(SMALL_DEFAULT)
    (tmp / "scripts").mkdir()
    shutil.copy(ROOT / "scripts" / "quickstart.sh", tmp / "scripts" / "quickstart.sh")
    shutil.copytree(ROOT / "benchmarks", tmp / "benchmarks", ignore=shutil.ignore_patterns("results", "__pycache__"))
    return tmp


#: What the README's ``python3 -m pytest`` lines collect: a module with slow and quick tests, so
#: that ``-m "not slow"`` selects some of them and leaves out others.
COLLECTED = "tests/studies/test_studies_regenerate.py"


def _is_pytest(command: str) -> bool:
    return command.split()[:3] == ["python3", "-m", "pytest"]


def _run(command: str, cwd: Path) -> subprocess.CompletedProcess:
    if _is_pytest(command):
        # the suite cannot run itself inside itself: one module is collected with the line's
        # options; with plain asserts, as rewriting them is checked by the suite's own run
        command = command + f" --collect-only -q -n 0 --assert=plain {COLLECTED}"
        cwd = ROOT
    # benchmarks at their smallest (benchmarks/smoke.py): the command runs, its numbers mean nothing
    env = {**os.environ, "AAEVAL_SKIP_INSTALL": "1", "PYTHONDONTWRITEBYTECODE": "1", "AAEVAL_BENCH_SMOKE": "1"}
    return subprocess.run(["bash", "-c", "set -euo pipefail; " + command], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=3600)



@pytest.mark.parametrize("command", COMMANDS)
def test_readme_command_exits_0(command, workspace):
    done = _run(command, workspace)
    assert done.returncode == 0, f"{command}\nexit {done.returncode}\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}"
    if _is_pytest(command):  # the line's options selected tests of the module
        assert re.search(rf"^{re.escape(COLLECTED)}: [1-9]", done.stdout, flags=re.M), done.stdout[-2000:]
    if command.startswith("bash scripts/quickstart.sh"):
        assert "cells:" in done.stdout  # progress lines although stdout is not a terminal
        assert (workspace / "reports" / "default" / "index.html").is_file()
