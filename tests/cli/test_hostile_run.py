"""scripts/hostile_run.py stays runnable and clean: its configs category (about 60 cases,
under a minute), the Python API, budgets and phases, and the cache and studies categories
must count no traceback, hang, write outside, lost row, wrong exit or memory blow-up. They
run in one process of the script, shared by the tests below (one interpreter and one import
of aaeval instead of three). The whole run (over 300 cases, several minutes) is run by hand:
``python3 scripts/hostile_run.py``."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROBLEMS = ("traceback", "hang", "outside", "rows", "exit", "memory")
CATEGORIES = ("configs", "api", "budgets", "phases", "cache", "studies")

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("hostile_run")]  # one worker runs the script once


@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    """The script's exit code and its counts, over :data:`CATEGORIES`."""
    tmp_path = tmp_path_factory.mktemp("hostile")
    out = tmp_path / "counts.json"
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "hostile_run.py"), "--only", *CATEGORIES,
                           "--json", str(out)], capture_output=True, text=True, timeout=2100, cwd=tmp_path)
    return done.returncode, json.loads(out.read_text())


def _clean(hostile, categories: tuple[str, ...]) -> dict:
    code, counts = hostile
    # a case with a problem (traceback, hang, outside, rows, exit, memory) is a failing case
    failing = [c for c in counts["failing"] if c["category"] in categories]
    assert not failing, failing
    assert all(counts[p] == 0 for p in PROBLEMS), counts  # none in the other categories of the run either
    assert code == 0, counts["failing"]
    return counts


def test_the_hostile_configs_are_all_clean(hostile):
    counts = _clean(hostile, ("configs",))
    assert counts["per_category"]["configs"] >= 50


def test_the_hostile_api_budgets_and_phases_are_all_clean(hostile):
    """The Python API's arguments, the budgets a user chooses (crow's k, repeats, 400-digit and
    out-of-range options) and far frames of phased animations under a peak-memory limit."""
    counts = _clean(hostile, ("api", "budgets", "phases"))
    assert {c: counts["per_category"][c] for c in ("api", "budgets", "phases")} == {"api": 34, "budgets": 15,
                                                                                    "phases": 6}


def test_the_hostile_cache_and_studies_are_all_clean(hostile):
    """Damaged reference cache entries (non-finite, huge or mistyped noise, NaN or oversized
    images, a FIFO, a link) named and rendered again; a cache path that is a file refused;
    hostile study folders refused before their sweep, nothing written outside."""
    counts = _clean(hostile, ("cache", "studies"))
    assert {c: counts["per_category"][c] for c in ("cache", "studies")} == {"cache": 17, "studies": 11}
