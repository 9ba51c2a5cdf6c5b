"""The measuring engine: from a scene and a method spec to the numbers of one record.

``aaeval compare``, every sweep cell (:mod:`aaeval.sweeps.tasks`), the sweep's
temporal table (:mod:`aaeval.sweeps.table`) and the specular study all measure
through these functions, so the same scene, method and frame give the same numbers
wherever they are measured:

- :func:`render_measured`: one untimed render of exactly the spec to be timed (every
  option: the filter, the specular method, k, spp: each may compile its own kernels) at
  this image size, once per process (:func:`aaeval.renderers.run.warm_up`), then
  ``repeats`` timed renders (sweep cells);
- :func:`render_reference`: the reference image and, for a seeded reference, its noise;
- :func:`frame_metrics`: every per-frame metric asked, each with the mask it declares;
- :func:`series_metrics`: every temporal metric asked over all frames of an animation;
- :func:`measure_frame`: render + intensity sum + per-frame metrics, failures recorded.

Metric values come only from the registered metric functions (:mod:`aaeval.metrics`);
masks only from :mod:`aaeval.metrics.masks`.
"""

from __future__ import annotations

import math
import statistics
import traceback
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from aaeval.metrics import (
    METRICS,
    build_mask,
    check_metric_names,
    compute_metric,
    compute_temporal_metric,
    intensity_sum,
    rmse,
)
from aaeval.metrics._pairs import maps_once_per_pair
from aaeval.metrics.perceptual import flip_map
from aaeval.sweeps.record import Failure

if TYPE_CHECKING:
    from aaeval.renderers.spec import MethodSpec

__all__ = ["Timing", "FrameMeasurement", "SceneCache", "render_measured", "render_reference",
           "reference_kind", "noise_spec", "frame_metrics", "series_metrics", "measure_frame",
           "check_image_metrics", "check_temporal_metrics", "mask_source", "scene_mask", "FrameJob",
           "measure_frames"]


@dataclass(frozen=True)
class Timing:
    """Render time of one image: median, min and max over ``repeats`` timed renders (seconds)."""

    render_s: float
    render_s_min: float
    render_s_max: float
    repeats: int

    @classmethod
    def of(cls, seconds: Sequence[float]) -> "Timing":
        return cls(float(statistics.median(seconds)), float(min(seconds)), float(max(seconds)), len(seconds))

    @classmethod
    def missing(cls, repeats: int) -> "Timing":
        return cls(math.nan, math.nan, math.nan, int(repeats))

    def fields(self, width: int, height: int) -> dict[str, float]:
        """The record's timing fields: these four plus ``megapixels`` and ``ms_per_mpix``."""
        megapixels = width * height / 1e6
        return {"render_s": self.render_s, "render_s_min": self.render_s_min, "render_s_max": self.render_s_max,
                "repeats": self.repeats, "megapixels": megapixels, "ms_per_mpix": self.render_s * 1e3 / megapixels}


class SceneCache:
    """Parsed scenes by content digest: each worker parses a scene document once.

    Sweep payloads carry the scene document (workers need not share a disk); the parsed
    :class:`~aaeval.scenes.Scene` and the masks built on its frames are kept here.
    """

    def __init__(self):
        self._scenes: dict[str, Any] = {}
        self._masks: dict[tuple[str, int, str], np.ndarray] = {}

    def scene(self, digest: str, document: Mapping[str, Any], source: str):
        scene = self._scenes.get(digest)
        if scene is None:
            from aaeval.scenes import parse_scene

            scene = self._scenes[digest] = parse_scene(document, source=source)
        return scene

    def mask(self, digest: str, scene, frame: int, name: str) -> np.ndarray:
        key = (digest, frame, name)
        if key not in self._masks:
            self._masks[key] = scene_mask(name, scene.at_frame(frame))
        return self._masks[key]

    def series_mask(self, digest: str, scene, frames: Sequence[int], name: str) -> np.ndarray:
        """The mask ``name`` on each of ``frames``, stacked (F, H, W)."""
        return np.stack([self.mask(digest, scene, k, name) for k in frames])

    def noise_weight(self, digest: str, scene, frame: int) -> np.ndarray:
        """:func:`aaeval.metrics.edges.noise_weight` of the scene at ``frame``, kept."""
        from aaeval.metrics.edges import noise_weight

        key = (digest, frame, "noise_weight")
        if key not in self._masks:
            self._masks[key] = noise_weight(scene.at_frame(frame))
        return self._masks[key]

    def exact_series(self, digest: str, scene, frames: Sequence[int]) -> np.ndarray:
        """The exact box-filtered image of each of ``frames`` (Catmull's area sampling of the
        flat polygons), stacked (F, H, W, 3): the truth the metrics needing ``exact`` read."""
        from aaeval.catmull import render_flat
        from aaeval.scenes.shaded import has_shaded

        if has_shaded(scene):
            raise ValueError("no exact renderer shades: the exact frames exist for flat scenes only")
        for k in frames:
            if (digest, k, "exact") not in self._masks:
                self._masks[(digest, k, "exact")] = render_flat(scene.at_frame(k))
        return np.stack([self._masks[(digest, k, "exact")] for k in frames])


def mask_source(source: str, scene) -> np.ndarray:
    """The render a mask is read from (:data:`aaeval.metrics.masks.SOURCES`), of ``scene`` at
    its frame: ``exact``, Catmull's box-filtered image (the flat kernel on a flat scene, the
    same bits as the ``catmull`` method, without parsing a spec inside the sweep);
    ``specular``, the specular term of the Mitsuba Phong ground truth at
    :data:`~aaeval.metrics.masks.HIGHLIGHT_SPP` (cached on disk)."""
    from aaeval.scenes.shaded import has_shaded

    if source == "exact":
        if has_shaded(scene):
            from aaeval.renderers import render

            return render(scene, "catmull")
        from aaeval.catmull import render_flat

        return render_flat(scene)
    if source == "specular":
        from aaeval.groundtruth import groundtruth_phong
        from aaeval.metrics.masks import HIGHLIGHT_SPP

        return groundtruth_phong(scene, spp=HIGHLIGHT_SPP)[1]
    raise ValueError(f"unknown mask source {source!r}")


def scene_mask(name: str, scene) -> np.ndarray:
    """The mask ``name`` of ``scene`` at its frame, bool (H, W), given the render it is read
    from (:func:`mask_source`) where it is read from one."""
    from aaeval.metrics.masks import MASKS

    mask = MASKS.get_entry(name)
    source = mask.source and mask.applies_to(scene)
    return build_mask(name, scene, mask_source(mask.source, scene) if source else None)


#: This process's scene cache (each worker process has its own).
SCENES = SceneCache()

def render_measured(scene, spec: MethodSpec, frame: int, repeats: int = 1) -> tuple[np.ndarray, Timing]:
    """Render ``scene`` at ``frame`` with ``spec``: the spec itself untimed once per process
    and image size (:func:`aaeval.renderers.run.warm_up`), then ``repeats`` timed
    renders, one budget check for all. The image returned is the last timed render's.
    """
    from aaeval.renderers import render_timed

    image, seconds = render_timed(scene, spec, frame=frame, repeats=repeats, rehearse=True)
    return image, Timing.of(seconds)


def reference_kind(spec: MethodSpec) -> str:
    """``exact`` (no noise), ``stochastic`` (has a seed: noise is measured) or ``deterministic``."""
    if spec.method.exact:
        return "exact"
    return "stochastic" if "seed" in spec.options else "deterministic"


def noise_spec(spec: MethodSpec) -> MethodSpec | None:
    """The same reference with the next seed, to measure its noise; None if it has no seed."""
    if spec.method.exact or "seed" not in spec.options:
        return None
    return spec.with_options(seed=int(spec.options["seed"]) + 1)


def exact_shading_bound(scene, spec, frame: int) -> float | None:
    """RMS over pixels of the per-pixel error bound of ``catmull:shading=exact`` on a scene
    with shaded objects (the quadrature's estimate; the image has no sampling noise), or
    None for any other reference."""
    from aaeval.scenes.shaded import has_shaded

    if spec.method.name != "catmull" or spec.options.get("shading") != "exact":
        return None
    at = scene.at_frame(frame)
    if not has_shaded(at):
        return None
    from aaeval.specular.exact import error_bound

    # the specular options alone: pixel filter, blending space and threads do not change the bound
    options = {k: v for k, v in spec.options.items() if k not in ("shading", "threads", "filter", "blend")}
    bound = error_bound(at, **options)  # the reference just rendered gives it, unless blended
    return float(np.sqrt(np.mean(bound ** 2)))


def render_reference(scene, spec: MethodSpec | str, frame: int, *, estimate_noise: bool) -> dict:
    """The reference image of one frame, its render time and noise level (``spec`` a
    string only where it arrives from another process that could not parse it).

    ``noise_rmse`` is 0 for an exact reference, the RMS of the per-pixel error bound for
    ``catmull:shading=exact`` on a shaded scene (:func:`exact_shading_bound`); for a seeded one (with ``estimate_noise``)
    the RMS per-pixel noise of one render, ``rmse(a, b) / sqrt(2)`` against a second render
    with the next seed; NaN when not measured. ``noise_by_metric``: for every RMS metric
    (:attr:`aaeval.metrics.Metric.rms`) that applies to the scene, that noise on the
    metric's own pixels, then the scale of its edge values' noise model and the noise of its
    other pixels (:func:`aaeval.metrics.agreement.noise_strata`); all 0 for an exact
    reference, absent when not measured.
    """
    from aaeval.renderers import MethodSpec, render_timed

    spec = MethodSpec.parse(spec)
    image, (seconds,) = render_timed(scene, spec, frame=frame)
    exact = reference_kind(spec) == "exact"
    noise = 0.0 if exact else math.nan
    bound = exact_shading_bound(scene, spec, frame)
    if bound is not None:
        # no sampling noise, but the quadrature's own error: its bound stands as the noise
        noise = bound
    twin = noise_spec(spec) if estimate_noise else None
    strata = _noise_strata(scene.at_frame(frame), image, image) if exact else None
    if twin is not None:
        other, _ = render_timed(scene, twin, frame=frame)
        noise = rmse(image, other) / math.sqrt(2.0)
        strata = _noise_strata(scene.at_frame(frame), image, other)
    out = {"image": image, "render_s": seconds, "noise_rmse": noise, "noise_spec": twin,
           "intensity_sum": intensity_sum(image)}
    if strata is not None:
        out["noise_by_metric"] = strata
    return out


def _noise_strata(scene, image: np.ndarray, twin: np.ndarray) -> dict[str, list[float]]:
    """Every applicable RMS metric's noise strata (:func:`aaeval.metrics.agreement.noise_strata`)."""
    from aaeval.metrics.agreement import noise_strata
    from aaeval.metrics.edges import noise_weight

    edge, weight = scene_mask("edge", scene), noise_weight(scene)
    out = {}
    for name, metric in METRICS.items():
        if metric.kind == "image" and metric.rms and metric.applies_to(scene):
            mask = scene_mask(metric.mask, scene) if metric.mask else np.ones(edge.shape, bool)
            out[name] = list(noise_strata(image, twin, mask, edge, weight))
    return out


def agreement(names: Sequence[str], reference: np.ndarray, image: np.ndarray, strata: Mapping[str, Sequence[float]],
              mask_of, weight: np.ndarray) -> dict[str, float]:
    """For every RMS metric of ``names`` whose noise strata are known: the fraction of its
    pixels (and channels) where ``image`` passes the per-pixel z-test against ``reference``
    (:func:`aaeval.metrics.agreement.z_test_pass_fraction`)."""
    from aaeval.metrics.agreement import z_test_pass_fraction

    out = {}
    for name in names:
        metric = METRICS[name]
        if not metric.rms or name not in strata:
            continue
        _, scale_edge, sigma_other = (math.nan if v is None else float(v) for v in strata[name])
        edge = mask_of("edge")
        mask = mask_of(metric.mask) if metric.mask else np.ones(edge.shape, bool)
        out[name] = z_test_pass_fraction(reference, image, mask, edge, scale_edge, sigma_other, weight=weight)
    return out


def check_image_metrics(names: Sequence[str]) -> tuple[str, ...]:
    """The per-frame metric names, checked against the registry (:class:`MetricError`)."""
    return check_metric_names(names, "image")


def check_temporal_metrics(names: Sequence[str]) -> tuple[str, ...]:
    """The temporal metric names, checked against the registry (:class:`MetricError`)."""
    return check_metric_names(names, "temporal")


def _context(metric, mask_of, exact_of=None) -> dict:
    context = {"mask": mask_of(metric.mask)} if metric.mask else {}
    if "exact" in metric.needs:
        if exact_of is None:
            raise ValueError(f"metric {metric.name!r} needs the exact frames, and none were given")
        context["exact"] = exact_of()
    return context


def frame_metrics(names: Sequence[str], reference: np.ndarray, image: np.ndarray,
                  mask_of) -> tuple[dict[str, float], dict[str, str]]:
    """Every per-frame metric in ``names`` of ``image`` against ``reference``.

    ``mask_of(name)`` returns the mask ``name`` of the scene at this frame. A metric that
    cannot judge the image is NaN with its error in the second dict; it spoils no other.
    """
    values, errors = {}, {}
    for name in names:
        metric = METRICS[name]
        try:
            values[name] = compute_metric(name, reference, image, **_context(metric, mask_of))
        except Exception as exc:  # noqa: BLE001 - one metric's failure is that metric's result
            values[name] = math.nan
            errors[name] = f"{type(exc).__name__}: {exc}"
    return values, errors


def not_finite_metrics(values: dict, errors: dict) -> str:
    """The metrics of ``values`` that are infinite on their bad side (``rmse=inf``) or not
    numbers at all, as text; empty when there are none. Such a cell fails: an infinite error
    is no measurement, and no ``fail_above`` threshold could judge it. NaN stays what it was:
    a metric that could not judge this image (a masked metric on a scene without its pixels),
    listed apart; infinity on a metric's good side is a perfect score (PSNR of identical
    images)."""
    bad = []
    for name, value in values.items():
        if name in errors:
            continue
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            bad.append(f"{name}={value!r}"[:80])
            continue
        metric = METRICS.get(name)
        worst = -math.inf if metric is not None and metric.higher_is_better else math.inf
        if number == worst:
            bad.append(f"{name}={value!r}"[:80])
    return ", ".join(bad)


def series_metrics(names: Sequence[str], references: Sequence[np.ndarray], images: Sequence[np.ndarray],
                   mask_of, exact_of=None) -> tuple[dict[str, float], dict[str, str]]:
    """Every temporal metric in ``names`` over all frames, in frame order.

    ``mask_of(name)`` returns the mask ``name`` stacked over the frames, (F, H, W);
    ``exact_of()`` the exact frames, (F, H, W, 3) (:meth:`SceneCache.exact_series`), for
    the metrics that need them.
    """
    values, errors = {}, {}
    frames_true, frames_test = np.stack(references), np.stack(images)
    for name in names:
        metric = METRICS[name]
        try:
            values[name] = compute_temporal_metric(name, frames_true, frames_test,
                                                   **_context(metric, mask_of, exact_of))
        except Exception as exc:  # noqa: BLE001
            values[name] = math.nan
            errors[name] = f"{type(exc).__name__}: {exc}"
    return values, errors


@dataclass
class FrameMeasurement:
    """What :func:`measure_frame` returns: the record's measured fields, the image and its FLIP map."""

    image: np.ndarray | None
    timing: Timing
    intensity_sum: float = math.nan
    metrics: dict[str, float] = field(default_factory=dict)
    metric_errors: dict[str, str] = field(default_factory=dict)
    error: str | None = None
    traceback: str | None = None
    agreement: dict[str, float] = field(default_factory=dict)
    #: why it failed (:class:`aaeval.sweeps.record.Failure`), None when it did not
    failure: Failure | None = None
    #: the per-pixel FLIP error (H, W) against the reference, stored beside the image for the viewer
    flip: np.ndarray | None = None

    def fields(self, width: int, height: int) -> dict[str, Any]:
        return {**self.timing.fields(width, height), "intensity_sum": self.intensity_sum, "metrics": self.metrics,
                "metric_errors": self.metric_errors, "error": self.error, "traceback": self.traceback,
                "agreement": self.agreement, "failure": None if self.failure is None else self.failure.value}


def _test_noise(scene, spec: MethodSpec, frame: int, image: np.ndarray,
                noise_by_metric: Mapping[str, Sequence[float]]) -> Mapping[str, Sequence[float]]:
    """The noise strata the z-test of a cell uses: the reference's, except against a
    noise-free reference (no stratum above 0: an exact truth), where a seeded method is
    judged within its own noise, measured as a reference's is (a second render with the next
    seed). Against an exact truth a Monte Carlo render (Mitsuba's cross-check row, jitter)
    always differs by its sampling noise; whether it agrees within that noise is the question."""
    twin_spec = noise_spec(spec)
    if twin_spec is None or any(v > 0 for strata in noise_by_metric.values() for v in strata):  # NaN: nothing pooled
        return noise_by_metric
    from aaeval.renderers import render_timed

    twin, _ = render_timed(scene, twin_spec, frame=frame)
    return _noise_strata(scene.at_frame(frame), image, twin)


def measure_frame(scene, spec: MethodSpec, frame: int, reference: np.ndarray | None, metrics: Sequence[str], *,
                  digest: str, repeats: int = 1, cache: SceneCache | None = None,
                  reference_error: str | None = None,
                  noise_by_metric: Mapping[str, Sequence[float]] | None = None,
                  keep_flip: bool = True) -> FrameMeasurement:
    """Render one frame (timed), then measure it against ``reference``; never raises for the
    cell's own failures: they come back as ``error`` (and every metric NaN).

    ``digest`` names the scene's content in ``cache`` (masks are kept per digest and frame).
    ``reference_error``: why there is no reference (the cell fails with this message).
    ``noise_by_metric``: the reference's noise strata (:func:`render_reference`); with them
    the record's ``agreement`` holds each RMS metric's z-test pass fraction. ``keep_flip``:
    also the per-pixel FLIP map (``flip``) a sweep stores for its viewer.
    """
    return measure_frames([FrameJob(scene, spec, frame, reference, metrics, digest=digest, repeats=repeats,
                                    cache=cache, reference_error=reference_error, noise_by_metric=noise_by_metric,
                                    keep_flip=keep_flip)])[0]


@dataclass
class FrameJob:
    """The arguments of one :func:`measure_frame`, for :func:`measure_frames`."""

    scene: Any
    spec: Any
    frame: int
    reference: np.ndarray | None
    metrics: Sequence[str]
    digest: str
    repeats: int = 1
    cache: SceneCache | None = None
    reference_error: str | None = None
    noise_by_metric: Mapping[str, Sequence[float]] | None = None
    keep_flip: bool = True


def measure_frames(jobs: Sequence[FrameJob]) -> list[FrameMeasurement]:
    """:func:`measure_frame` of each job, the same numbers, in two passes: every frame
    rendered (timed) first, then the per-pixel maps that several of them need computed
    together (the CIEDE2000 maps of every pair of one size in one call,
    :func:`aaeval.metrics.colour_difference.ciede2000_maps`), then each frame measured."""
    from aaeval.metrics.colour_difference import ciede2000_maps

    outs = [_rendered(job) for job in jobs]
    with maps_once_per_pair():  # one FLIP for the metric and the viewer's map, one CIEDE2000 map
        if any({"ciede2000_mean", "ciede2000_p95"} & set(job.metrics) for job in jobs):
            ciede2000_maps([(job.reference, out.image) for job, out in zip(jobs, outs) if out.error is None])
        for job, out in zip(jobs, outs):
            if out.error is None:
                _measured(job, out)
    return outs


def _failed(out: FrameMeasurement, exc: Exception, failure: Failure = Failure.METHOD) -> None:
    out.error, out.failure = f"{type(exc).__name__}: {exc}", failure
    out.traceback = traceback.format_exc(limit=6)


def _rendered(job: FrameJob) -> FrameMeasurement:
    """The job's frame rendered (timed) and checked, or its failure."""
    out = FrameMeasurement(None, Timing.missing(job.repeats), metrics={m: math.nan for m in job.metrics})
    if job.reference_error:
        try:
            raise RuntimeError(job.reference_error)
        except RuntimeError as exc:  # raised here so that its traceback is stored like any failure's
            _failed(out, exc, Failure.REFERENCE)
            return out
    try:
        image, out.timing = render_measured(job.scene, job.spec, job.frame, job.repeats)
        out.image = image
        if not np.all(np.isfinite(image)):
            raise FloatingPointError("the image has non-finite pixels")
        out.intensity_sum = intensity_sum(image)
    except Exception as exc:  # noqa: BLE001 - a failing cell is a result, not the end of the run
        _failed(out, exc)
    return out


def _measured(job: FrameJob, out: FrameMeasurement) -> None:
    """The metrics, FLIP map and z-test of a rendered frame into ``out``, or its failure."""
    cache, scene, frame, reference, image = job.cache or SCENES, job.scene, job.frame, job.reference, out.image

    def mask_of(name):
        return cache.mask(job.digest, scene, frame, name)

    try:
        out.metrics, out.metric_errors = frame_metrics(job.metrics, reference, image, mask_of)
        if job.keep_flip:
            out.flip = flip_map(reference, image)
        not_finite = not_finite_metrics(out.metrics, out.metric_errors)
        if not_finite:  # an image too far from its reference to measure: a failed cell, not a number
            raise FloatingPointError(f"metric(s) infinite: {not_finite}; the image is too far from its "
                                     "reference to be measured")
        if job.noise_by_metric:
            out.agreement = agreement(job.metrics, reference, image,
                                      _test_noise(scene, job.spec, frame, image, job.noise_by_metric), mask_of,
                                      cache.noise_weight(job.digest, scene, frame))
    except Exception as exc:  # noqa: BLE001 - a failing cell is a result, not the end of the run
        _failed(out, exc)
