"""Durations and test counts go stale in prose: the README and the developer guide point at
the dated table in benchmarks/results/timings.md instead of quoting them."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TIMINGS = ROOT / "benchmarks" / "results" / "timings.md"
# "4 min 59 s", "229-265 s", "1962 tests", "2,323 tests": a measured time or a count of tests
QUOTED = re.compile(r"\b\d+(?:[.,]\d+)?\s*min\s+\d+\s*s\b|\b\d+(?:-\d+)?\s*s\b(?= quiet| on 2 cores)|\b\d[\d,]*\s+tests\b")


def test_readme_and_development_guide_quote_no_durations_or_test_counts():
    for path in (ROOT / "README.md", ROOT / "docs" / "development.md"):
        found = QUOTED.findall(path.read_text(encoding="utf-8"))
        assert not found, f"{path.name} quotes {found}: put the measurement in {TIMINGS.relative_to(ROOT)}"


def test_the_timings_table_is_dated():
    rows = [line for line in TIMINGS.read_text(encoding="utf-8").splitlines() if re.match(r"\| \d{4}-\d\d-\d\d \|", line)]
    assert rows, "benchmarks/results/timings.md has no dated measurement"
    assert all(line.count("|") == 7 for line in rows), "each row: date, machine, what, command, wall time, notes"
