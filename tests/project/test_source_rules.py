"""Rules on the code itself, kept by a test so they stay kept: every C++ source and every
module of the package readable in one sitting (at most 500 lines), one reader of the
environment's limits, no trace of the numba kernels the native ones replaced, and a README
short enough to be a guide (at most 200 lines)."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SOURCES = sorted(p for p in (ROOT / "src").rglob("*") if p.suffix in {".cpp", ".hpp", ".h", ".cc"})


def test_the_sources_are_found():
    assert len(SOURCES) > 20


MODULES = sorted((ROOT / "aaeval").rglob("*.py"))
#: the modules that read the environment: the limits (aaeval.limits), where the ground-truth
#: cache lives, and where Mitsuba's libLLVM is
READS_ENVIRONMENT = {"aaeval/limits.py", "aaeval/groundtruth/cache.py", "aaeval/mitsuba_variant.py"}


@pytest.mark.parametrize("path", SOURCES + MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_source_file_is_over_500_lines(path):
    lines = len(path.read_text().splitlines())
    assert lines <= 500, f"{path.relative_to(ROOT)}: {lines} lines"


def test_only_the_limits_the_cache_and_the_llvm_finder_read_the_environment():
    readers = {str(p.relative_to(ROOT)) for p in MODULES
               if re.search(r"os\.environ\.get\(|os\.getenv\(|environ\[[^]]+\](?!\s*=)", p.read_text())}
    assert readers <= READS_ENVIRONMENT, sorted(readers - READS_ENVIRONMENT)


def test_no_word_numba_in_the_package_or_the_kernels():
    found = [str(p.relative_to(ROOT)) for folder in ("src", "aaeval") for p in (ROOT / folder).rglob("*")
             if p.suffix in {".py", ".cpp", ".hpp", ".txt", ".js"} and "numba" in p.read_text().lower()]
    assert not found, found


def test_the_readme_is_at_most_200_lines():
    assert len((ROOT / "README.md").read_text().splitlines()) <= 200
