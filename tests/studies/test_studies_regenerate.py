"""The committed studies are what the command writes: regenerating a study's sweep gives the
committed measured part of its README, all but the date, machine and timing lines
(:func:`aaeval.studies.readme.measured_part`), and every figure it shows is drawn.

The four studies take about 15 s of CPU with a cold reference cache (amanatides1992 about
11 s, each other one 1-3 s): the smallest runs in the default suite, all four under
``-m slow``. Each sweep runs in the test's own process (``workers=1``): the
numbers do not depend on the executor (the executors have their own tests), and two worker
processes cost more to start than these few small cells take. Nothing is written into
experiments/: the sweep, the drawings and the figures go to a temporary folder."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from aaeval.studies.readme import BEGIN, END, measured_part, read_readme
from aaeval.studies.section import generate_section
from aaeval.studies.study import load_study

ROOT = Path(__file__).resolve().parents[2]
STUDIES = sorted(p.parent for p in (ROOT / "experiments").glob("*/study.toml"))
SMALLEST = ROOT / "experiments" / "weiler-atherton1977"


def _committed(folder: Path) -> str:
    text = read_readme(folder / "README.md")
    return text.split(BEGIN, 1)[1].split(END, 1)[0].strip()


def _regenerate(folder: Path, tmp_path: Path) -> str:
    from dataclasses import replace

    from aaeval.sweeps import run_sweep

    study = replace(load_study(folder, results=tmp_path / "results"), drawings=tmp_path / "drawings")
    summary = run_sweep(study.experiment, study.results, workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert not summary.lost and not summary.failed
    return generate_section(study)


def _check(folder: Path, tmp_path: Path) -> None:
    section = _regenerate(folder, tmp_path)
    committed = _committed(folder)
    assert measured_part(section) == measured_part(committed), (
        f"{folder.name}: the committed README differs from what 'aaeval study {folder.relative_to(ROOT)}' writes; "
        "run it and commit the README")
    # every figure the README shows was drawn, and is committed beside it
    shown = re.findall(r"\]\(((?:figures|hidden-lines)/[^)]+)\)", committed)
    for rel in shown:
        assert (tmp_path / "drawings" / rel).is_file(), rel
        assert (folder / rel).is_file(), f"{folder.name}/{rel} is shown in the README but not committed"


# memory_tmp_path: a sweep folder, its cache and the drawings are hundreds of small files
@pytest.mark.slow
def test_the_smallest_study_regenerates_as_committed(memory_tmp_path):
    _check(SMALLEST, memory_tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("folder", [s for s in STUDIES if s != SMALLEST], ids=lambda p: p.name)
def test_every_study_regenerates_as_committed(folder, memory_tmp_path):
    _check(folder, memory_tmp_path)


@pytest.mark.parametrize("folder", STUDIES, ids=lambda p: p.name)
def test_every_study_readme_shows_its_figures(folder):
    committed = _committed(folder)
    figures = re.findall(r"!\[[^\]]+\]\((figures/[^)]+\.png)\)", committed)
    assert figures, f"{folder.name}: its README shows no figure"
    for rel in figures:
        path = folder / rel
        assert path.is_file() and path.stat().st_size < 400_000, rel  # committed, and small
