"""Compare rendering methods against a reference, frame by frame, on one scene.

:func:`plan_comparison` checks everything (scene, method specs, frames, metrics) before any
rendering; :func:`run_comparison` measures through the same engine as a sweep cell
(:mod:`aaeval.sweeps.measure`) and returns a JSON-ready document (write it with
:func:`aaeval.sweeps.typed_json.dumps`: strict JSON, NaN and infinities as their tags).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from aaeval.sweeps.measure import (
    SceneCache,
    check_image_metrics,
    check_temporal_metrics,
    measure_frame,
    render_reference,
    series_metrics,
)
from aaeval.metrics import default_metrics, relative_variation
from aaeval.options import MAX_INT
from aaeval.renderers import MethodSpec
from aaeval.renderers.budget import check_frames
from aaeval.scenes import Scene, load_scene

__all__ = ["ComparisonPlan", "parse_frames", "plan_comparison", "run_comparison"]


@dataclass(frozen=True)
class ComparisonPlan:
    """A validated comparison: the scene, the specs, the frames and metrics to measure."""

    scene: Scene
    methods: tuple[MethodSpec, ...]  # parsed once, canonical
    reference: MethodSpec
    frames: tuple[int, ...]
    metrics: tuple[str, ...]
    temporal: tuple[str, ...]
    repeats: int = 1

    @property
    def renders(self) -> int:
        """How many images the comparison renders (timed repeats counted once)."""
        return len(self.frames) * (1 + len(self.methods))


def parse_frames(value: str | int, available: int) -> tuple[int, ...]:
    """Frames to render: ``"all"``, or ``N`` for the first N of ``available``."""
    if isinstance(value, str) and value.strip().lower() == "all":
        return tuple(range(available))
    try:
        count = int(value)
    except (TypeError, ValueError):
        raise ValueError(f"--frames must be a positive number or 'all', got {value!r}") from None
    if count < 1:
        raise ValueError(f"--frames must be at least 1, got {count}")
    if count > available:
        raise ValueError(f"--frames {count}: the scene has only {available} frame(s)")
    return tuple(range(count))


def _frame_count(value: str | int, available: int) -> int:
    """How many frames ``--frames value`` asks for (0 when malformed: parse_frames says why)."""
    if isinstance(value, str) and value.strip().lower() == "all":
        return available
    try:
        return max(0, min(int(value), available))
    except (TypeError, ValueError):
        return 0


def plan_comparison(
    scene: str | Scene,
    methods: Sequence[str],
    reference: str,
    frames: str | int = 1,
    metrics: Sequence[str] | None = None,
    temporal: Sequence[str] | None = None,
    repeats: int = 1,
) -> ComparisonPlan:
    """Check every input and return the plan; raises before anything is rendered.

    ``metrics`` and ``temporal`` default to every registered metric of their kind that
    applies to the scene (:func:`aaeval.metrics.default_metrics`).

    Raises
    ------
    MethodError
        A bad method or reference spec.
    SceneError
        A scene file that breaks the scene format.
    MetricError
        An unknown metric.
    ValueError
        No methods, a method given twice, bad frames or repeats.
    """
    if not methods:
        raise ValueError("give at least one --method to compare")
    reference = MethodSpec.parse(reference)  # the specs enter here, parsed once
    seen: dict[MethodSpec, str] = {}
    for text in methods:
        spec = MethodSpec.parse(text)  # a MethodSpec already parsed is taken as it is
        if spec in seen:
            raise ValueError(f"method {text.strip()!r} is the same as {seen[spec]!r}; give each method once")
        seen[spec] = text.strip()
    methods = tuple(seen)
    if metrics is not None:
        metrics = check_image_metrics(metrics)
    if temporal is not None:
        temporal = check_temporal_metrics(temporal)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or not 1 <= repeats <= MAX_INT:
        shown = "a larger integer" if isinstance(repeats, int) and repeats > MAX_INT else repr(repeats)
        raise ValueError(f"--repeats must be a whole number in [1, {MAX_INT}] (and fit the time limit), got {shown}")
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    metrics = default_metrics("image", [scene]) if metrics is None else metrics
    temporal = default_metrics("temporal", [scene]) if temporal is None else temporal
    # a file's frame count is budgeted as a generator's, before the frame list is built
    check_frames(scene, _frame_count(frames, scene.frames), f"--frames {frames} --repeats {repeats}",
                 specs=(reference, *methods), held=1 + len(methods), repeats=repeats)
    return ComparisonPlan(scene, methods, reference, parse_frames(frames, scene.frames), metrics,
                          temporal, repeats)


def run_comparison(plan: ComparisonPlan, *, on_render: Callable[[str, int], None] | None = None) -> dict:
    """Render every method and the reference on the plan's frames and measure them.

    Parameters
    ----------
    plan : ComparisonPlan
        From :func:`plan_comparison`.
    on_render : callable, optional
        Called as ``on_render(spec, frame)`` after each image is rendered (progress).

    Returns
    -------
    document : dict
        ``scene``, ``width``, ``height``, ``reference``, ``frames``, ``metrics``,
        ``temporal``, ``repeats``; ``rows``: per method and frame ``method``, ``frame``,
        each metric, ``intensity_sum``, the timing fields (``render_s`` median,
        ``render_s_min``, ``render_s_max``, ``repeats``, ``megapixels``, ``ms_per_mpix``),
        ``error`` and ``metric_errors``; ``reference_rows``: the reference's ``frame``,
        ``intensity_sum`` and ``render_s``; ``reference_summary``: its ``sum_variation`` and
        ``render_s_median``; ``summary``: per method ``mean`` (each metric's mean over the
        frames), ``temporal`` (each temporal metric over the frames, when there are at
        least two), ``reference_sum_variation``, ``render_s_median``. A value that is not a
        finite number is NaN here and ``null`` in JSON.
    """
    scene = plan.scene
    cache = SceneCache()
    digest = "compare"
    reference_frames, reference_rows, rows = [], [], []
    method_frames: dict[str, list[np.ndarray]] = {spec: [] for spec in plan.methods}
    for k in plan.frames:
        ref = render_reference(scene, plan.reference, k, estimate_noise=False)
        _notify(on_render, plan.reference, k)
        reference_frames.append(ref["image"])
        reference_rows.append({"frame": k, "intensity_sum": ref["intensity_sum"], "render_s": ref["render_s"]})
        for spec in plan.methods:
            measured = measure_frame(scene, spec, k, ref["image"], plan.metrics, repeats=plan.repeats,
                                     digest=digest, cache=cache, keep_flip=False)  # no viewer here
            _notify(on_render, spec, k)
            method_frames[spec].append(measured.image)
            fields = measured.fields(scene.width, scene.height)
            rows.append({"method": spec, "frame": k, **fields.pop("metrics"), **fields})
            rows[-1].pop("traceback")
            rows[-1].pop("agreement")  # no second truth here to test against
    reference_variation = relative_variation([r["intensity_sum"] for r in reference_rows])
    summary = []
    for spec in plan.methods:
        own = [r for r in rows if r["method"] == spec]
        failed = any(r["error"] for r in own)
        temporal = {name: float("nan") for name in plan.temporal}
        temporal_errors: dict[str, str] = {}
        if len(plan.frames) >= 2 and not failed:
            temporal, temporal_errors = series_metrics(
                plan.temporal, reference_frames, method_frames[spec],
                lambda name: cache.series_mask(digest, scene, plan.frames, name),
                lambda: cache.exact_series(digest, scene, plan.frames))
        summary.append(
            {
                "method": spec,
                "frames": len(own),
                "failed_frames": sum(bool(r["error"]) for r in own),
                "mean": {name: float(np.mean([r[name] for r in own])) for name in plan.metrics},
                "temporal": temporal,
                "temporal_errors": temporal_errors,
                "reference_sum_variation": reference_variation,
                "render_s_median": float(np.median([r["render_s"] for r in own])),
            }
        )
    return {
        "scene": scene.source,
        "width": scene.width,
        "height": scene.height,
        "reference": plan.reference,
        "frames": list(plan.frames),
        "metrics": list(plan.metrics),
        "temporal": list(plan.temporal),
        "repeats": plan.repeats,
        "rows": rows,
        "reference_rows": reference_rows,
        "reference_summary": {
            "method": plan.reference,
            "frames": len(reference_rows),
            "sum_variation": reference_variation,
            "render_s_median": float(np.median([r["render_s"] for r in reference_rows])),
        },
        "summary": summary,
    }


def _notify(on_render, spec: str, frame: int) -> None:
    if on_render is not None:
        on_render(spec, frame)
