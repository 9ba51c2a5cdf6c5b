"""The work a sweep sends to its workers: plain top-level functions of plain data, so that
local processes and Dask workers run exactly the same code.

Neither function touches the sweep folder: they return results, and the process that
drives the sweep writes them. Workers of a cluster need not share its disk.
"""

from __future__ import annotations

import math
import os
import socket
import time
import traceback
from typing import Any

import numpy as np

__all__ = ["render_reference", "run_cell", "reference_kind", "noise_spec"]


def reference_kind(spec: str) -> str:
    """``exact`` (no noise), ``stochastic`` (has a seed: noise is measured) or ``deterministic``."""
    from aaeval.renderers import resolve

    method, options = resolve(spec)
    if method.exact:
        return "exact"
    return "stochastic" if "seed" in options else "deterministic"


def noise_spec(spec: str) -> str | None:
    """The same reference with the next seed, to measure its noise; None if it has no seed."""
    from aaeval.renderers import format_spec, resolve

    method, options = resolve(spec)
    if method.exact or "seed" not in options:
        return None
    return format_spec(method.name, {**options, "seed": int(options["seed"]) + 1})


def render_reference(document: dict, source: str, frame: int, spec: str, estimate_noise: bool) -> dict:
    """Render a reference frame; for a seeded reference also its noise level.

    The noise level is the RMS per-pixel noise of one render, estimated from a second
    render with the next seed: ``rmse(a, b) / sqrt(2)``. A reference that fails comes
    back as ``{"error": ...}``.
    """
    from aaeval.renderers import render_timed
    from aaeval.scenes import parse_scene

    try:
        scene = parse_scene(document, source=source)
        image, seconds = render_timed(scene, spec, frame=frame)
        noise = 0.0 if reference_kind(spec) == "exact" else math.nan
        twin = noise_spec(spec) if estimate_noise else None
        if twin is not None:
            other, _ = render_timed(scene, twin, frame=frame)
            noise = float(np.sqrt(np.mean((image - other) ** 2)) / math.sqrt(2.0))
    except Exception as exc:  # the cells that need it record this as their error
        return {"error": f"{type(exc).__name__}: {exc}", "host": socket.gethostname()}
    return {"image": image, "render_s": seconds, "noise_rmse": noise, "noise_spec": twin,
            "host": socket.gethostname()}


_WARMED: set[tuple] = set()


def _warm_up(scene, spec: str, frame: int) -> None:
    """Render once untimed the first time this process meets a (spec, image size).

    ``render_timed`` warms a method up once, but a JIT such as Dr.Jit compiles a new
    kernel for each sample count and image size: without this the first cell of each
    option would be timed with its compilation.
    """
    from aaeval.renderers import render

    key = (spec, scene.width, scene.height)
    if key not in _WARMED:
        render(scene, spec, frame=frame)
        _WARMED.add(key)


def run_cell(payload: dict[str, Any]) -> tuple[dict, np.ndarray | None]:
    """Render one cell, compare it with its reference image; never raises for the cell's
    own failures: they come back as the record's ``error``."""
    from aaeval.experiments.metrics import frame_metric
    from aaeval.metrics import intensity_sum
    from aaeval.renderers import render_timed
    from aaeval.scenes import parse_scene

    record = dict(payload["record"])
    record.update(host=socket.gethostname(), pid=os.getpid(), error=None, render_s=math.nan,
                  metrics={m: math.nan for m in payload["metrics"]}, intensity_sum=math.nan)
    image = None
    try:
        if payload.get("reference_error"):
            raise RuntimeError(f"reference {payload['record']['reference']} failed: {payload['reference_error']}")
        scene = parse_scene(payload["document"], source=payload["source"])
        _warm_up(scene, record["spec"], record["frame"])
        image, seconds = render_timed(scene, record["spec"], frame=record["frame"])
        record["render_s"] = seconds
        if not np.all(np.isfinite(image)):
            raise FloatingPointError("the image has non-finite pixels")
        record["intensity_sum"] = intensity_sum(image)
        reference = payload["reference_image"]
        at_frame = scene.at_frame(record["frame"])
        for name in payload["metrics"]:
            try:
                record["metrics"][name] = frame_metric(name, reference, image, scene=at_frame)
            except Exception as exc:  # one metric that cannot judge this image spoils no other
                record.setdefault("metric_errors", {})[name] = f"{type(exc).__name__}: {exc}"
    except Exception as exc:  # a failing cell is a result, not the end of the sweep
        record["error"] = f"{type(exc).__name__}: {exc}"
        record["traceback"] = traceback.format_exc(limit=6)
    record["finished_at"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
    return record, image
