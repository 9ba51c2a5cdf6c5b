"""Running a study: its sweep run or resumed, the run's wall time recorded beside it, and the
README's generated section written again from the results."""

from __future__ import annotations

import json
import time
from datetime import datetime, timezone
from pathlib import Path

from aaeval.studies.folder import OUTPUT_FOLDERS, Study, refuse_link
from aaeval.studies.readme import read_readme, replace_section
from aaeval.studies.section import RUN_FILE, generate_section


class IncompleteSweep(RuntimeError):
    """Some cells of the study's sweep could not run (a worker died); they run on the next try.
    The README is left as it was: a section from part of the cells would misstate the study."""


def run_study(study: Study, *, run: bool = True, workers: int | None = None, quiet: bool = True,
              cache_dir: str | Path | None = None, now: datetime | None = None) -> str:
    """Run (or resume) the study's sweep, then rewrite the README's generated section.

    Parameters
    ----------
    study : Study
        From :func:`load_study`.
    run : bool
        False: only read the existing results folder (the sweep must have finished).
    workers : int, optional
        Local worker processes of the sweep (default: every core).
    quiet : bool
        No progress bars.
    cache_dir : str or Path, optional
        Reference cache folder (default ``$AAEVAL_CACHE_DIR`` or ``~/.cache/aaeval``).
    now : datetime, optional
        The date written in the section (tests pass a fixed one).

    Returns
    -------
    str
        The generated section, as written into the README.
    """
    from aaeval.sweeps import load_experiment, run_sweep
    from aaeval.imageio import atomic_write

    for name in OUTPUT_FOLDERS:  # again: the folder may have been swapped for a link since load_study
        refuse_link(study.output / name)

    experiment = study.experiment or load_experiment(study.config)
    if run:
        start = time.perf_counter()
        summary = run_sweep(experiment, study.results, workers=workers, quiet=quiet, cache_dir=cache_dir)
        wall = time.perf_counter() - start
        if summary.lost:
            raise IncompleteSweep(f"{study.results}: {len(summary.lost)} cell(s) could not run ({summary.lost[0]}); "
                                  "finished cells are kept, run the study again")
        if summary.ran:  # a rerun that found everything done keeps the time of the run that did the work
            record = {"wall_s": wall, "cells_run": summary.ran, "cells": summary.total, "failed": summary.failed,
                      "executor": summary.executor,
                      "finished_at": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")}
            atomic_write(study.results / RUN_FILE,
                         lambda tmp: Path(tmp).write_text(json.dumps(record, indent=1) + "\n"))
    section = generate_section(study, now=now)
    refuse_link(study.readme)
    new = replace_section(read_readme(study.readme), section, study.readme)
    atomic_write(study.readme, lambda tmp: Path(tmp).write_text(new, encoding="utf-8"))
    return section
