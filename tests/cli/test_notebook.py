"""The example notebook: examples/notebook.py runs top to bottom as a
script, and writes its two figures (error against time, the images)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "examples" / "notebook.py"


def test_notebook_cells_are_percent_cells():
    cells = [line for line in NOTEBOOK.read_text().splitlines() if line.startswith("# %%")]
    assert len(cells) >= 8 and cells[0] == "# %% [markdown]"


@pytest.mark.slow
def test_notebook_runs_and_draws_its_figures(tmp_path):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "AAEVAL_NOTEBOOK_OUT": str(tmp_path), "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(NOTEBOOK)], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    for name in ("error-vs-time.png", "images.png"):
        with Image.open(tmp_path / name) as figure:
            assert figure.size[0] >= 800  # a real figure, not an empty file
