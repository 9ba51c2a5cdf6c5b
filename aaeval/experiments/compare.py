"""Compare rendering methods against a reference, frame by frame, on one scene.

:func:`plan_comparison` checks everything (scene, method specs, frames) before any
rendering; :func:`run_comparison` renders and measures, and returns a JSON-ready
document: one row per method and frame (every image metric of :data:`IMAGE_METRICS`, the
intensity sum and the render time) and a temporal summary per method.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from aaeval.metrics import (
    IMAGE_METRICS,
    MetricError,
    compute_metric,
    compute_temporal_metric,
    edge_mask,
    intensity_sum,
    sum_variation,
)
from aaeval.renderers import format_spec, render_timed, resolve
from aaeval.scenes import Scene, load_scene

__all__ = ["ComparisonPlan", "parse_frames", "plan_comparison", "run_comparison"]


@dataclass(frozen=True)
class ComparisonPlan:
    """A validated comparison: the scene, the specs and the frames to render."""

    scene: Scene
    methods: tuple[str, ...]
    reference: str
    frames: tuple[int, ...]
    metrics: tuple[str, ...] = tuple(IMAGE_METRICS)

    @property
    def renders(self) -> int:
        """How many images the comparison renders."""
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


def plan_comparison(
    scene: str | Scene,
    methods: Sequence[str],
    reference: str,
    frames: str | int = 1,
    metrics: Sequence[str] | None = None,
) -> ComparisonPlan:
    """Check every input and return the plan; raises before anything is rendered.

    Raises
    ------
    MethodError
        A bad method or reference spec.
    SceneError
        A scene file that breaks the scene format.
    ValueError
        No methods, a method given twice, bad frames or an unknown metric.
    """
    if not methods:
        raise ValueError("give at least one --method to compare")
    methods = tuple(spec.strip() for spec in methods)
    resolve(reference)
    seen: dict[str, str] = {}
    for spec in methods:
        method, options = resolve(spec)
        canonical = format_spec(method.name, options)
        if canonical in seen:
            raise ValueError(f"method {spec!r} is the same as {seen[canonical]!r}; give each method once")
        seen[canonical] = spec
    metrics = tuple(IMAGE_METRICS) if metrics is None else tuple(metrics)
    unknown = [m for m in metrics if m not in IMAGE_METRICS]
    if unknown:
        raise MetricError(f"unknown metric(s) {unknown}; available: {', '.join(IMAGE_METRICS)}")
    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    return ComparisonPlan(scene, methods, reference.strip(), parse_frames(frames, scene.frames), metrics)


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
        ``scene``, ``width``, ``height``, ``reference``, ``frames``, ``metrics``;
        ``rows``: per method and frame ``method``, ``frame``, each metric, ``intensity_sum``
        and ``render_s`` (the render alone, JIT warm-up excluded); ``reference_rows``: the
        reference's ``frame``, ``intensity_sum`` and ``render_s``; ``reference_summary``: its
        ``sum_variation`` and ``render_s_median``; ``summary``: per method ``mean`` (each
        metric's mean over the frames), ``sum_variation`` (of its intensity sums over the frames), ``flicker`` (of its error
        against the reference), ``reference_sum_variation``, ``render_s_median``.
    """
    scene = plan.scene
    reference_frames = []
    reference_rows = []
    method_frames: dict[str, list[np.ndarray]] = {spec: [] for spec in plan.methods}
    rows = []
    for k in plan.frames:
        truth, seconds = render_timed(scene, plan.reference, frame=k)
        _notify(on_render, plan.reference, k)
        reference_frames.append(truth)
        reference_rows.append({"frame": k, "intensity_sum": intensity_sum(truth), "render_s": seconds})
        context = {"mask": edge_mask(scene.at_frame(k))} if "edge_rmse" in plan.metrics else {}
        for spec in plan.methods:
            image, seconds = render_timed(scene, spec, frame=k)
            _notify(on_render, spec, k)
            method_frames[spec].append(image)
            row = {"method": spec, "frame": k}
            row.update({name: compute_metric(name, truth, image, **context) for name in plan.metrics})
            row.update(intensity_sum=intensity_sum(image), render_s=seconds)
            rows.append(row)
    reference_variation = sum_variation([r["intensity_sum"] for r in reference_rows])
    summary = []
    for spec in plan.methods:
        own = [r for r in rows if r["method"] == spec]
        summary.append(
            {
                "method": spec,
                "frames": len(own),
                "mean": {name: float(np.mean([r[name] for r in own])) for name in plan.metrics},
                "sum_variation": sum_variation([r["intensity_sum"] for r in own]),
                "flicker": compute_temporal_metric("flicker", reference_frames, method_frames[spec]),
                "reference_sum_variation": reference_variation,
                "render_s_median": statistics.median(r["render_s"] for r in own),
            }
        )
    return {
        "scene": scene.source,
        "width": scene.width,
        "height": scene.height,
        "reference": plan.reference,
        "frames": list(plan.frames),
        "metrics": list(plan.metrics),
        "rows": rows,
        "reference_rows": reference_rows,
        "reference_summary": {
            "method": plan.reference,
            "frames": len(reference_rows),
            "sum_variation": reference_variation,
            "render_s_median": statistics.median(r["render_s"] for r in reference_rows),
        },
        "summary": summary,
    }


def _notify(on_render, spec: str, frame: int) -> None:
    if on_render is not None:
        on_render(spec, frame)
