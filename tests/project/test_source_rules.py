"""Issue 34's rules on the code itself, kept by a test so they stay kept: every C++ source
readable in one sitting (at most 600 lines), no trace of the numba kernels the native ones
replaced, and a README short enough to be a guide (at most 200 lines)."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCES = sorted(p for p in (ROOT / "src").rglob("*") if p.suffix in {".cpp", ".hpp", ".h", ".cc"})


def test_the_sources_are_found():
    assert len(SOURCES) > 20


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_source_file_is_over_600_lines(path):
    lines = len(path.read_text().splitlines())
    assert lines <= 600, f"{path.relative_to(ROOT)}: {lines} lines"


def test_no_word_numba_in_the_package_or_the_kernels():
    found = [str(p.relative_to(ROOT)) for folder in ("src", "aaeval") for p in (ROOT / folder).rglob("*")
             if p.suffix in {".py", ".cpp", ".hpp", ".txt", ".js"} and "numba" in p.read_text().lower()]
    assert not found, found


def test_the_readme_is_at_most_200_lines():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 200
