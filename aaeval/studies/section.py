"""The generated section of a study's README, written from the sweep's stored results: the
provenance lines, each summary under its title, and the count of expectations that hold."""

from __future__ import annotations

import json
import re
from datetime import datetime, timezone
from pathlib import Path

from aaeval.studies.folder import Study, StudyError
from aaeval.studies.markdown import md_code, md_text
from aaeval.studies.readme import BEGIN, END, GENERATED, MACHINE
from aaeval.studies.summaries import SUMMARIES


#: The run record the tool keeps beside the sweep (the sweep's wall time is not in its tables).
RUN_FILE = "study_run.json"


def generate_section(study: Study, now: datetime | None = None) -> str:
    """The generated section's markdown, read from ``study.results``.

    Raises
    ------
    StudyError
        The results folder holds no finished sweep, or a summary names a group, method or
        metric that is not in it.
    """
    from aaeval.api import open_sweep
    from aaeval.sweeps.provenance import read_provenance

    if not (study.results / "results.parquet").is_file():
        raise StudyError(f"{study.results}: no results.parquet; run 'aaeval study {study.folder}' without --no-run")
    from aaeval.readlimits import read_bytes

    stored = study.results / "experiment.toml"
    if stored.is_file() and read_bytes(stored, what="stored config") != read_bytes(study.config, what="experiment config"):
        # the numbers would describe another version of the study: never written as this one's
        raise StudyError(f"{study.results}: its sweep ran another version of {study.config}; run "
                         f"'aaeval study {study.folder}' without --no-run")
    sweep = open_sweep(study.results)
    results = sweep.results
    provenance = read_provenance(study.results) or {}
    run = _run_record(study.results)
    now = now or datetime.now(timezone.utc)
    failed = int(results["error"].notna().sum()) if "error" in results else 0
    machine = ", ".join(str(provenance[k]) for k in ("cpu_model", "cores") if provenance.get(k) is not None)
    lines = [
        f"{GENERATED} {now.strftime('%Y-%m-%d %H:%M UTC')} by {md_code('aaeval study ' + study.folder.as_posix())} "
        f"from the sweep in {md_code(study.results.name + '/')} ({len(results)} cells, {failed} failed; "
        f"code {md_text(provenance.get('code_version', '?'))}).",
        f"{MACHINE} {md_text(machine or 'not recorded')} cores, {md_text(provenance.get('executor', 'executor not recorded'))}."
        + (f" The sweep ran {int(run['cells_run'])} cells in {float(run['wall_s']):.1f} s of wall time." if run else ""),
    ]
    checks: list[bool] = []  # one per expectation of study.toml, in order
    body: list[str] = []
    for i, item in enumerate(study.summaries):
        summary = SUMMARIES[item["kind"]]
        where = f"{study.folder / 'study.toml'}: summaries[{i}]"
        body += ["", f"### {md_text(item.get('title', summary.title))}", ""]
        if item.get("note"):
            body += [md_text(item["note"]), ""]
        body += summary.write(sweep, item, study, where, checks)
    if checks:
        lines += ["", f"**Expectations** (the claim as `study.toml` states it, checked against these results): "
                  f"{sum(checks)} of {len(checks)} hold."]
    section = re.sub(r"\n{3,}", "\n\n", "\n".join(lines + body))  # one blank line between blocks
    if BEGIN in section or END in section:  # escaped above; a README the next run refuses is never written
        raise StudyError(f"{study.folder / 'study.toml'}: the generated text holds a study marker")
    return section


def _run_record(results: Path) -> dict | None:
    path = results / RUN_FILE
    if not path.is_file():
        return None
    from aaeval.readlimits import read_bytes

    try:
        record = json.loads(read_bytes(path, what="run record", limit=1 << 16))
        float(record["wall_s"]), int(record["cells_run"])
    except (OSError, ValueError, KeyError, TypeError):
        return None  # a damaged run record loses only the time line, never the numbers
    return record
