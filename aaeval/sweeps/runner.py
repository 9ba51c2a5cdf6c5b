"""Running a sweep: plan the cells, render the missing references, run the missing cells,
write each result as it arrives, rebuild the results table.

A rerun of the same config into the same folder skips every finished cell (failed ones
too: their error is their result; ``retry_failed`` runs them again).
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterator

import numpy as np

from aaeval.sweeps.cache_keys import cell_key, code_version, reference_key
from aaeval.sweeps.cells import Cell
from aaeval.sweeps.config import Experiment
from aaeval.sweeps.config_keys import ConfigError
from aaeval.sweeps.executors import make_executor
from aaeval.sweeps.measure import reference_kind
from aaeval.sweeps.provenance import write_provenance
from aaeval.sweeps.record import SCHEMA_VERSION, Failure
from aaeval.sweeps.reference_cache import ReferenceCache, ReferenceInfo, cache_folder_problem
from aaeval.sweeps.store import SweepStore
from aaeval.sweeps.task_failures import SchedulerLost, TaskTimedOut, WorkerDied
from aaeval.sweeps.tasks import failed_record, run_cell, run_cells, run_reference
from aaeval.plugins import cell_plugins

if TYPE_CHECKING:
    from aaeval.renderers import MethodSpec

__all__ = ["PlannedCell", "plan", "manifest", "record_identity", "run_sweep", "SweepSummary", "progress_bar"]


@dataclass
class PlannedCell:
    cell: Cell
    key: str
    reference_key: str

    def manifest_row(self) -> dict:
        c = self.cell
        return {"key": self.key, "group": c.group, "scene": c.scene_source.name, "difficulty": c.scene_source.difficulty,
                "difficulty_label": c.scene_source.difficulty_label, "scene_digest": c.scene_source.digest, "spec": c.spec,
                "frame": c.frame, "reference": c.reference, "reference_key": self.reference_key,
                "frames": c.scene_source.frames, "repeats": c.repeats,
                "plugins": cell_plugins(c.spec, c.metrics)}


def plan(experiment: Experiment) -> list[PlannedCell]:
    """Every cell of the config with its key: one key per (group, scene, difficulty, spec, frame).

    Raises
    ------
    ConfigError
        Two cells with one key: the config repeats itself (the message names both).
    """
    version = code_version()
    planned = [PlannedCell(c, cell_key(cell_identity(c), version),
                           reference_key(c.scene_source.digest, c.frame, c.reference, _with_plugins(version, c.reference)))
               for c in experiment.cells()]
    seen: dict[str, PlannedCell] = {}
    for p in planned:
        if p.key in seen:
            a, b = seen[p.key].cell, p.cell
            raise ConfigError(f"{experiment.path}: group {b.group!r} scene {b.scene_source.name!r} {b.spec} frame {b.frame} "
                              f"is given twice (also as group {a.group!r} scene {a.scene_source.name!r}); give each cell once")
        seen[p.key] = p
    return planned


def cell_identity(cell: Cell) -> dict:
    """What a cell's key is made of: :meth:`Cell.identity` and, when its method, clamp or a
    metric comes from a plugin, those plugins (name, version, digest of their code files),
    so that an edited plugin reruns its cells; a cell of built-ins keeps its key."""
    identity = cell.identity()
    plugins = cell_plugins(cell.spec, cell.metrics)
    if plugins:
        identity["plugins"] = plugins
    return identity


def _with_plugins(version: str, reference: MethodSpec) -> str:
    """The code version a reference image depends on: aaeval's, and its plugin's if any."""
    plugins = cell_plugins(reference)
    return version + "".join(f"+{p['distribution']}={p['version']}:{p['files']}" for p in plugins)


def manifest(experiment: Experiment, planned: list[PlannedCell]) -> dict:
    """What ``manifest.json`` holds: the experiment's settings, every cell, every scene document.

    The scene documents (by digest) let the table rebuild masks for temporal metrics from the
    folder alone.
    """
    scenes = {}
    for p in planned:
        scenes.setdefault(p.cell.scene_source.digest, {"source": p.cell.scene_source.source, "document": p.cell.scene_source.document})
    return {"experiment": experiment.name, "description": experiment.description, "config": experiment.path,
            "schema_version": SCHEMA_VERSION, "code_version": code_version(), "primary": experiment.primary,
            "fail_above": experiment.fail_above,
            "metrics": list(dict.fromkeys(m for g in experiment.groups for m in g.metrics)),
            "temporal": list(dict.fromkeys(m for g in experiment.groups for m in g.temporal)),
            "group_temporal": {g.name: list(g.temporal) for g in experiment.groups},
            "cells": [p.manifest_row() for p in planned], "scenes": scenes}


@dataclass
class SweepSummary:
    total: int  # distinct cells
    skipped: int  # finished before this run
    ran: int = 0
    failed: int = 0  # ran and recorded an error
    lost: list[str] = field(default_factory=list)  # could not run (worker died): not recorded
    references_rendered: int = 0
    references_cached: int = 0
    executor: str = ""
    #: every failed cell of the config (this run's and earlier runs' that were kept), by the
    #: first line of its error: the cells' descriptions (group, scene, spec, frame)
    errors: dict[str, list[str]] = field(default_factory=dict)
    #: failed cells recorded by earlier runs and kept (rerun them with retry_failed)
    failed_before: int = 0

    #: why the cluster could not run the cells (lost, not answering, no worker left), the
    #: first such reason; None when no cluster failed
    cluster_lost: str | None = None

    def note_lost(self, exc: BaseException) -> None:
        """Keep ``exc`` as the cluster's reason when it is one (:class:`SchedulerLost`)."""
        if isinstance(exc, SchedulerLost) and self.cluster_lost is None:
            self.cluster_lost = str(exc)

    def add_error(self, error: str, cell: str) -> None:
        self.errors.setdefault(error.strip().splitlines()[0] if error.strip() else "error", []).append(cell)


class _LineProgress:
    """Progress as plain lines, for a stdout that is not a terminal (a log file, CI, a pipe):
    a task's count, elapsed time and estimate at most every ``every`` seconds, and when it ends."""

    def __init__(self, every: float = 15.0, stream=None):
        import sys

        self.every, self.stream = every, stream or sys.stdout
        self.tasks: dict[int, dict] = {}

    def add_task(self, description: str, total: int) -> int:
        import time

        task = len(self.tasks)
        now = time.monotonic()
        self.tasks[task] = {"description": description, "total": int(total), "done": 0, "start": now, "shown": now}
        self._line(task)
        return task

    def advance(self, task: int, advance: int = 1) -> None:
        import time

        t = self.tasks[task]
        t["done"] += advance
        now = time.monotonic()
        if now - t["shown"] >= self.every or t["done"] >= t["total"]:
            t["shown"] = now
            self._line(task)

    def _line(self, task: int) -> None:
        import time

        t = self.tasks[task]
        elapsed = time.monotonic() - t["start"]
        eta = (f", eta {elapsed / t['done'] * (t['total'] - t['done']):.0f} s"
               if 0 < t["done"] < t["total"] else "")
        print(f"{t['description']}: {t['done']}/{t['total']} ({elapsed:.0f} s{eta})", file=self.stream, flush=True)


@contextmanager
def progress_bar(quiet: bool):
    """A rich progress bar with counts and ETA on a terminal, plain progress lines when stdout
    is not one, or nothing under ``--quiet``."""
    import sys

    if quiet:
        yield None
        return
    if not sys.stdout.isatty():
        yield _LineProgress()
        return
    from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn,
                               TimeRemainingColumn)

    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TextColumn("elapsed"),
                  TimeElapsedColumn(), TextColumn("eta"), TimeRemainingColumn()) as progress:
        yield progress


def record_identity(p: PlannedCell, ref_meta: dict) -> dict:
    """The record fields known before the cell runs (:class:`~aaeval.sweeps.record.CellRecord`)."""
    c = p.cell
    options = dict(c.spec.options)
    return {
        "key": p.key, "group": c.group, "code_version": code_version(), "scene": c.scene_source.name,
        "scene_source": c.scene_source.source, "scene_digest": c.scene_source.digest, "difficulty": c.scene_source.difficulty,
        "difficulty_label": c.scene_source.difficulty_label,
        "method": c.spec.name, "spec": c.spec, "options": options, "frame": c.frame,
        "spp": options.get("spp"), "seed": options.get("seed"),
        "reference": c.reference, "reference_key": p.reference_key, "reference_kind": reference_kind(c.reference),
        "reference_spp": c.reference.options.get("spp"), "reference_seed": c.reference.options.get("seed"),
        "reference_noise_rmse": ref_meta.get("noise_rmse", math.nan),
        # the truth's noise on each RMS metric's own pixels (the first of its strata)
        "reference_noise": {name: strata[0] for name, strata in (ref_meta.get("noise_by_metric") or {}).items()
                            if name in c.metrics},
        "reference_intensity_sum": ref_meta.get("intensity_sum", math.nan),
        "width": c.scene_source.parsed.width, "height": c.scene_source.parsed.height,
    }


def run_sweep(experiment: Experiment, out: str | Path, *, workers: int | None = None, scheduler: Any = None,
              quiet: bool = False, retry_failed: bool = False, cache_dir: str | Path | None = None,
              force: bool = False, log=print) -> SweepSummary:
    """Run every unfinished cell of ``experiment`` into the folder ``out``.

    The folder is locked for the run (a second sweep into it is refused), and a folder of
    another experiment is refused unless ``force``: nothing in it is replaced before then.
    """
    problem = cache_folder_problem(cache_dir)
    if problem:  # before any work: every reference would fail with it
        raise ValueError(problem)
    store = SweepStore(out)
    planned = plan(experiment)
    with store.lock():
        store.check_experiment(experiment.name, {p.key for p in planned}, force=force)
        summary = _run_locked(experiment, store, planned, workers=workers, scheduler=scheduler, quiet=quiet,
                              retry_failed=retry_failed, cache_dir=cache_dir, log=log)
        if experiment.speed and not summary.lost:
            from aaeval.sweeps.speed import run_speed_pass

            # after the accuracy cells, in this process: one worker, the stated threads
            run_speed_pass(experiment, store.root, log=(lambda *_: None) if quiet else log)
            from aaeval.sweeps.report_files import write_summary_tables

            write_summary_tables(store)  # the speed pass's summary and the findings that read it
        return summary


def _run_locked(experiment, store, planned, *, workers, scheduler, quiet, retry_failed, cache_dir,
                log=print) -> SweepSummary:
    from aaeval.sweeps.report_files import write_sweep_files

    def write_manifest():  # only once the run can start: a failed start leaves the folder as it was
        store.write_manifest(experiment.text, manifest(experiment, planned))

    unique: dict[str, PlannedCell] = {}
    for p in planned:
        unique.setdefault(p.key, p)
    sound = store.check(heal=True)
    for key, record in list(sound.items()):  # a record edited to another cell's identity runs again
        p = unique.get(key)
        if p is not None and _disagrees(record, p):
            store.set_aside(key, f"its group, scene, spec or frame differs from the config's "
                                 f"({p.cell.group!r}, {p.cell.scene_source.name!r}, {p.cell.spec}, {p.cell.frame})")
            del sound[key]
    # a cell whose worker died or was stopped at the time limit is retried by a plain rerun;
    # one whose method answered with an error only under --retry-failed
    finished = {k for k, r in sound.items()
                if not (r["failure"] and Failure(r["failure"]).retried) and not (retry_failed and r["failure"])}
    todo = [p for k, p in unique.items() if k not in finished]
    summary = SweepSummary(total=len(unique), skipped=len(unique) - len(todo))
    for key in finished:
        if key in unique and sound[key].get("error"):
            summary.failed_before += 1
            summary.add_error(sound[key]["error"], describe(unique[key]))
    if not todo:
        write_manifest()
        write_sweep_files(store)
        return summary

    executor = make_executor(workers, scheduler, experiment.max_seconds)
    write_manifest()
    summary.executor = executor.description
    write_provenance(store.root, executor.description, executor.workers)
    try:
        with progress_bar(quiet) as progress:
            refs = _references(experiment, todo, store, ReferenceCache(cache_dir and Path(cache_dir) / "references"),
                               executor, progress, summary)
            _cells(todo, refs, store, executor, progress, summary)
    finally:
        executor.close()
    write_sweep_files(store)
    return summary


def describe(p: PlannedCell) -> str:
    """A cell as a reader finds it in the config: group, scene, spec and frame."""
    c = p.cell
    return f"{c.group} / {c.scene_source.name} / {c.spec} / frame {c.frame}"


def _disagrees(record: dict, p: PlannedCell) -> bool:
    c = p.cell
    return (record.get("group") != c.group or record.get("scene") != c.scene_source.name
            or record.get("spec") != str(c.spec) or record.get("frame") != c.frame)


def _references(experiment, todo, store, cache, executor, progress, summary) -> dict[str, dict]:
    """Reference image metadata per reference key; images land in the sweep folder."""
    wanted: dict[str, PlannedCell] = {}
    for p in todo:
        wanted.setdefault(p.reference_key, p)
    meta: dict[str, dict] = {}
    missing = []
    for key, p in wanted.items():
        hit = cache.get(key, (p.cell.scene_source.parsed.height, p.cell.scene_source.parsed.width, 3))
        if (hit is not None and experiment.noise_estimate and hit[1].noise_by_metric is None
                and reference_kind(p.cell.reference) != "deterministic"):  # a deterministic one has no noise
            hit = None  # cached by a sweep that did not measure its noise: render it again
        if hit is not None:
            image, info = hit
            store.write_reference(key, image)
            meta[key] = info.as_meta()
            summary.references_cached += 1
        else:
            missing.append(p)
    task = progress.add_task("references", total=len(missing)) if progress and missing else None
    payloads = [(p.cell.scene_source.document, p.cell.scene_source.source, p.cell.frame, p.cell.reference,
                 experiment.noise_estimate, p.cell.scene_source.digest) for p in missing]
    for i, result, exc in executor.run(run_reference, payloads):
        key = missing[i].reference_key
        if exc is not None:  # the worker died: its cells wait for the next run
            meta[key] = {"lost": f"{type(exc).__name__}: {exc}"}
            summary.note_lost(exc)
        elif "error" in result:
            meta[key] = {"error": result["error"]}
        else:
            info = ReferenceInfo.of(missing[i].cell.reference, result)
            cache.put(key, result["image"], info)
            store.write_reference(key, result["image"])
            meta[key] = info.as_meta()
            summary.references_rendered += 1
        if task is not None:
            progress.advance(task)
    return meta


def _cells(todo, refs, store, executor, progress, summary) -> None:
    # timings are only comparable between cells that shared the machine the same way
    run = {"executor": executor.description, "workers": executor.workers}
    task = progress.add_task("cells", total=len(todo)) if progress else None
    loaded: dict[str, np.ndarray] = {}

    def payloads() -> Iterator[tuple]:
        for p in todo:
            info = refs.get(p.reference_key, {})
            if p.reference_key not in loaded and "error" not in info:
                loaded[p.reference_key] = store.load_reference(p.reference_key)
            yield ({"identity": record_identity(p, info), "run": run, "document": p.cell.scene_source.document,
                    "source": p.cell.scene_source.source, "metrics": list(p.cell.metrics), "repeats": p.cell.repeats,
                    "reference_image": loaded.get(p.reference_key), "reference_error": info.get("error"),
                    "noise_by_metric": info.get("noise_by_metric")},)

    lost = [p for p in todo if "lost" in refs.get(p.reference_key, {})]
    summary.lost += [f"{p.key}: reference not rendered ({refs[p.reference_key]['lost']})" for p in lost]
    todo = [p for p in todo if "lost" not in refs.get(p.reference_key, {})]
    if task is not None:
        progress.advance(task, len(lost))
    work = list(payloads())
    with _batched_writes(store) as write:
        for indices, outcome, exc in _run_in_chunks(executor, work):
            if isinstance(exc, (WorkerDied, TaskTimedOut)):  # the cell's own doing: recorded as failed
                (i,) = indices
                failure = Failure.TIMED_OUT if isinstance(exc, TaskTimedOut) else Failure.WORKER_DIED
                write(failed_record(work[i][0], str(exc), failure), None, None)
                summary.ran += 1
                summary.failed += 1
                summary.add_error(str(exc), describe(todo[i]))
            elif exc is not None:
                summary.lost += [f"{todo[i].key}: {type(exc).__name__}: {exc}" for i in indices]
                summary.note_lost(exc)
            else:
                for i, (record, image, flip) in zip(indices, outcome):
                    if hasattr(executor, "current"):  # a cluster's workers now (one may have died since the start)
                        record.update(executor.current())
                    write(record, image, flip)
                    summary.ran += 1
                    if record.get("error"):
                        summary.failed += 1
                        summary.add_error(record["error"], describe(todo[i]))
            if task is not None:
                progress.advance(task, len(indices))


#: Most cells in one task, and most cells and seconds between two writes of the store.
CHUNK_CELLS = 16
BATCH_CELLS = 64
BATCH_SECONDS = 1.0


def chunks(count: int, workers: int, most: int = CHUNK_CELLS) -> list[range]:
    """``range(count)`` cut into consecutive chunks for ``workers``: each an eighth of the
    cells left per worker (at most ``most``), so chunks shrink towards the end and no worker
    waits long for another's last chunk."""
    out, start = [], 0
    while start < count:
        size = max(1, min(most, (count - start) // (8 * max(1, workers))))
        out.append(range(start, min(count, start + size)))
        start += size
    return out


def _run_in_chunks(executor, work: list[tuple]) -> Iterator[tuple[tuple[int, ...], Any, BaseException | None]]:
    """Run every cell of ``work`` in chunks (:func:`run_cells`), yielding ``(indices, results,
    error)`` per chunk. A chunk whose worker died or ran past the time limit runs again one
    cell per task, so that the cell that did it is the one recorded as failed, alone."""
    parts = [tuple(r) for r in chunks(len(work), executor.workers)]
    again = []
    for j, results, exc in executor.run(run_cells, [([work[i][0] for i in part],) for part in parts]):
        if isinstance(exc, (WorkerDied, TaskTimedOut)) and len(parts[j]) > 1:
            again += parts[j]
        else:
            yield parts[j], results, exc
    for k, result, exc in executor.run(run_cell, [work[i] for i in again]):
        yield (again[k],), None if exc is not None else [result], exc


@contextmanager
def _batched_writes(store):
    """``write(record, image, flip)`` for finished cells, written to ``store`` in batches
    (:meth:`SweepStore.write_cells`, its syncs shared): a batch is written when a cell
    arrives and the batch then holds :data:`BATCH_CELLS` cells or its first cell has waited
    :data:`BATCH_SECONDS`, and the rest when the block ends, however it ends (an error,
    Ctrl-C). A sweep killed outright loses the cells in flight: those still computing and
    those waiting in the batch."""
    import time

    batch: list[tuple] = []
    since = 0.0

    def write(record, image, flip) -> None:
        nonlocal since
        if not batch:
            since = time.monotonic()
        batch.append((record, image, flip))
        if len(batch) >= BATCH_CELLS or time.monotonic() - since >= BATCH_SECONDS:
            flush()

    def flush() -> None:
        if batch:
            store.write_cells(batch)
            batch.clear()

    try:
        yield write
    finally:
        flush()
