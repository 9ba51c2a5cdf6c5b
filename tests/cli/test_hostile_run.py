"""scripts/hostile_run.py stays runnable and clean: its configs category (about 60 cases,
under a minute) must count no traceback, hang, write outside, lost row or wrong exit. The
whole run (over 300 cases, several minutes) is run by hand: ``python3 scripts/hostile_run.py``."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_the_hostile_configs_are_all_clean(tmp_path):
    out = tmp_path / "counts.json"
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "hostile_run.py"), "--only", "configs",
                           "--json", str(out)], capture_output=True, text=True, timeout=600, cwd=tmp_path)
    counts = json.loads(out.read_text())
    assert done.returncode == 0, [c for c in counts["failing"]]
    assert counts["cases"] >= 50
    assert all(counts[p] == 0 for p in ("traceback", "hang", "outside", "rows", "exit")), counts


@pytest.mark.slow
def test_the_hostile_api_budgets_and_phases_are_all_clean(tmp_path):
    """The Python API's arguments, the budgets a user chooses (crow's k, repeats, 400-digit and
    out-of-range options) and far frames of phased animations under a peak-memory limit."""
    out = tmp_path / "counts.json"
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "hostile_run.py"), "--only", "api", "budgets",
                           "phases", "--json", str(out)], capture_output=True, text=True, timeout=900, cwd=tmp_path)
    counts = json.loads(out.read_text())
    assert done.returncode == 0, [c for c in counts["failing"]]
    assert counts["per_category"] == {"api": 34, "budgets": 15, "phases": 6}
    assert all(counts[p] == 0 for p in ("traceback", "hang", "outside", "rows", "exit", "memory")), counts


@pytest.mark.slow
def test_the_hostile_cache_and_studies_are_all_clean(tmp_path):
    """Damaged reference cache entries (non-finite, huge or mistyped noise, NaN or oversized
    images, a FIFO, a link) named and rendered again; a cache path that is a file refused;
    hostile study folders refused before their sweep, nothing written outside."""
    out = tmp_path / "counts.json"
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "hostile_run.py"), "--only", "cache", "studies",
                           "--json", str(out)], capture_output=True, text=True, timeout=600, cwd=tmp_path)
    counts = json.loads(out.read_text())
    assert done.returncode == 0, [c for c in counts["failing"]]
    assert counts["per_category"] == {"cache": 17, "studies": 11}
    assert all(counts[p] == 0 for p in ("traceback", "hang", "outside", "rows", "exit", "memory")), counts
