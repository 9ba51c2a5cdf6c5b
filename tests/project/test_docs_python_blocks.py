"""Docs that run: every ```python block of README.md and docs/*.md runs as
written and raises nothing.

A page's blocks run in order in one fresh interpreter, sharing their names (as cells of a
notebook do), in a temporary folder that sees the repository's ``configs/`` and
``examples/`` (links), so the paths the docs name resolve and what the blocks write lands
in the temporary folder. A block that is not meant to run (it reads a report that only a
long sweep writes) is fenced ``py`` instead of ``python``: shown the same, not run.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LINKED = ("configs", "examples")

# each block runs with exec(); a failure names the page's line where its block starts
RUNNER = """
import json, sys, traceback
blocks = json.load(open(sys.argv[1]))
names = {"__name__": "__main__"}
for line, source in blocks:
    try:
        exec(compile(source, f"{sys.argv[2]}:block at line {line}", "exec"), names)
    except BaseException:
        traceback.print_exc()
        print(f"FAILED: the python block at line {line} of {sys.argv[2]}", file=sys.stderr)
        sys.exit(1)
"""


def python_blocks(text: str) -> list[tuple[int, str]]:
    """(line of the opening fence, code) of every block fenced exactly ``python``."""
    return [(text.count("\n", 0, m.start()) + 1, m.group(1))
            for m in re.finditer(r"^```python[ \t]*\n(.*?)^```", text, flags=re.S | re.M)]


def test_blocks_are_found():
    text = "intro\n```python\nx = 1\n```\n```py\nnot run\n```\n```python\ny = x\n```\n"
    assert python_blocks(text) == [(2, "x = 1\n"), (8, "y = x\n")]
    assert python_blocks((ROOT / "docs" / "python.md").read_text())  # the API page has some


def _pages_with_blocks() -> list[Path]:
    return [p for p in PAGES if python_blocks(p.read_text())]


@pytest.mark.slow
@pytest.mark.parametrize("page", _pages_with_blocks(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_python_blocks_run_as_written(page, tmp_path):
    for name in LINKED:
        (tmp_path / name).symlink_to(ROOT / name)
    blocks = tmp_path / "blocks.json"
    blocks.write_text(json.dumps(python_blocks(page.read_text())))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-c", RUNNER, str(blocks), page.relative_to(ROOT).as_posix()],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
