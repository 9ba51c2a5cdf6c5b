"""The work a sweep sends to its workers: plain top-level functions of plain data, so that
local processes and Dask workers run exactly the same code.

A spec crosses to a worker as its text: a Dask scheduler unpickles every task, in a
process where no method is registered, so a :class:`MethodSpec` would reach the worker as
the plain string it falls back to there. Each task parses its specs itself
(:func:`worker_spec`), after loading the registries, so it runs the same wherever it lands.

Neither function touches the sweep folder: they return results, and the process that
drives the sweep writes them. Workers of a cluster need not share its disk. Both measure
through :mod:`aaeval.sweeps.measure`, the engine ``aaeval compare`` uses too; each
worker parses a scene document once (:data:`aaeval.sweeps.measure.SCENES`).
"""

from __future__ import annotations

import os
import socket
import time
from typing import Any

import numpy as np

from aaeval import registries
from aaeval.sweeps.measure import SCENES, FrameJob, FrameMeasurement, Timing, measure_frames, render_reference
from aaeval.sweeps.record import CellRecord, Failure
from aaeval.renderers.spec import MethodSpec

__all__ = ["run_reference", "run_cell", "run_cells", "failed_record", "worker_spec"]


def worker_spec(spec: MethodSpec | str) -> MethodSpec:
    """``spec`` as the worker's own :class:`MethodSpec`: its text parsed against this
    process's registries, loaded first (a task may reach a worker that has run none)."""
    registries.load()
    return MethodSpec.parse(spec)


def run_reference(document: dict, source: str, frame: int, spec: MethodSpec, estimate_noise: bool,
                  digest: str) -> dict:
    """Render a reference frame (:func:`aaeval.sweeps.measure.render_reference` on the
    scene document); for a seeded reference also its noise level.

    A reference that fails comes back as ``{"error": ...}``.
    """
    try:
        spec = worker_spec(spec)
        scene = SCENES.scene(digest, document, source)
        result = render_reference(scene, spec, frame, estimate_noise=estimate_noise)
    except Exception as exc:  # noqa: BLE001 - the cells that need it record this as their error
        return {"error": f"{type(exc).__name__}: {exc}", "host": socket.gethostname()}
    return {**result, "host": socket.gethostname()}


def run_cell(payload: dict[str, Any]) -> tuple[dict, np.ndarray | None, np.ndarray | None]:
    """Render one cell, compare it with its reference image; never raises for the cell's
    own failures: they come back as the record's ``error``.

    ``payload``: ``identity`` (the record's identity and reference fields), ``run``
    (``executor``, ``workers``), ``document``, ``source``, ``metrics``, ``repeats``,
    ``reference_image``, ``reference_error``. Returns the record as strict-JSON-ready dict
    (:meth:`CellRecord.to_json`), the image and its FLIP map against the reference.
    """
    return run_cells([payload])[0]


def failed_record(payload: dict[str, Any], error: str, failure: Failure) -> dict:
    """The record of a cell that never answered (its worker died or was stopped at the time
    limit: ``failure``), built in the sweep's process from the payload it sent: failed with
    ``error``, every metric NaN, no image."""
    measured = FrameMeasurement(None, Timing.missing(payload["repeats"]),
                                metrics={m: float("nan") for m in payload["metrics"]}, error=error, failure=failure)
    return _answer(payload, measured)[0]


def run_cells(payloads: list[dict[str, Any]]) -> list[tuple[dict, np.ndarray | None, np.ndarray | None]]:
    """:func:`run_cell` of each payload of a chunk, in order: one task, one message each way
    for many cells, and the per-pixel maps the cells share computed together
    (:func:`aaeval.sweeps.measure.measure_frames`)."""
    jobs = [_frame_job(payload) for payload in payloads]
    return [_answer(payload, measured) for payload, measured in zip(payloads, measure_frames(jobs))]


def _frame_job(payload: dict[str, Any]) -> FrameJob:
    identity = payload["identity"]
    try:
        identity = {**identity, "spec": worker_spec(identity["spec"]), "reference": worker_spec(identity["reference"])}
        scene = SCENES.scene(identity["scene_digest"], payload["document"], payload["source"])
    except Exception as exc:  # noqa: BLE001 - cannot happen for a checked config; recorded if it does
        scene, parse_error = None, f"{type(exc).__name__}: {exc}"
    else:
        parse_error = None
    return FrameJob(
        scene, identity["spec"], identity["frame"], payload["reference_image"], payload["metrics"],
        repeats=payload["repeats"], digest=identity["scene_digest"], cache=SCENES,
        noise_by_metric=payload.get("noise_by_metric"),
        reference_error=parse_error or (payload.get("reference_error") and
                                        f"reference {identity['reference']} failed: {payload['reference_error']}"))


def _answer(payload: dict[str, Any], measured: FrameMeasurement) -> tuple[dict, np.ndarray | None, np.ndarray | None]:
    """The cell's record (strict-JSON-ready), image and FLIP map."""
    identity = payload["identity"]
    record = CellRecord(
        **identity, **measured.fields(identity["width"], identity["height"]), **payload["run"],
        host=socket.gethostname(), pid=os.getpid(),
        finished_at=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()))
    return record.to_json(), measured.image, measured.flip
