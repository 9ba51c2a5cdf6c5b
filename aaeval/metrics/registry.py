"""Metrics by name, with everything known about them, in colour-science's style
(``colour.difference.DELTA_E_METHODS`` and ``colour.delta_E``).

:data:`METRICS` is the only place a metric is known: :func:`register_metric` adds one with
its title, number format, direction (higher or lower is better) and what it needs to be
computed (the reference, the scene, a mask, every frame). ``aaeval compare``, sweeps, the
results table, the report and ``aaeval metrics`` all read it from there, so adding a metric
is one registration and nothing else.

Two kinds:

- ``image`` metrics ``metric(image_true, image_test, **options) -> float`` on one frame,
  (H, W, 3) linear RGB;
- ``temporal`` metrics ``metric(frames_true, frames_test, **options) -> float`` on every
  frame of an animation, (F, H, W, 3).

A metric that declares a ``mask`` receives it as the keyword option ``mask``; masks are
built from the scene by :mod:`aaeval.metrics.masks` (shape (H, W) for image metrics,
(F, H, W) for temporal ones). The names are stable: sweeps and reports address metrics by
them.
"""

from __future__ import annotations

import functools
import inspect
from dataclasses import dataclass
from typing import Any, Callable, Mapping

from aaeval.metrics.colour_difference import ciede2000_mean, ciede2000_p95
from aaeval.metrics.edges import edge_rmse
from aaeval.metrics.image import psnr, rmse, ssim
from aaeval.metrics.perceptual import flip
from aaeval.metrics.specular import (
    highlight_bias,
    highlight_energy_bias,
    highlight_energy_flicker,
    highlight_profile_flicker,
    highlight_flicker,
    highlight_rmse,
)
from aaeval.metrics.temporal import flicker, image_flicker, sum_bias, sum_variation, temporal_bias
from aaeval.metrics.video import CVVDP_MODULE, cvvdp
from aaeval.metrics.info import MetricInfo, format_value
from aaeval.options import Registry

__all__ = [
    "METRICS",
    "IMAGE_METRICS",
    "TEMPORAL_METRICS",
    "KINDS",
    "NEEDS",
    "Metric",
    "MetricError",
    "register_metric",
    "get_metric",
    "default_metrics",
    "check_metric_names",
    "compute_metric",
    "compute_temporal_metric",
    "format_value",
]


class MetricError(ValueError):
    """An unknown metric name, an unknown option, or a required option missing."""


KINDS = ("image", "temporal")
#: What a metric may need: the reference image(s), the scene, every frame of an animation,
#: the exact box-filtered frames (keyword ``exact``: Catmull's area sampling of the scene's
#: flat polygons; such a metric applies to unshaded scenes only). (A mask is declared by
#: name in :attr:`Metric.mask`.)
NEEDS = ("reference", "scene", "frames", "exact")


@dataclass(frozen=True)
class Metric(MetricInfo):
    """One registered metric: its description (:class:`~aaeval.metrics.info.MetricInfo`)
    and ``func(true, test, **options) -> float``."""

    func: Callable[..., float] | None = None
    requires: str | None = None  # a module the function imports, not installed with aaeval itself
    extra: str | None = None  # the optional-dependency group of aaeval that installs it
    # measured when a config or a comparison names no metrics of its kind; False for a costly
    # one (a perceptual model) that is asked for by name
    by_default: bool = True

    def unavailable(self) -> str | None:
        """Why this metric cannot be computed on this machine, or None when it can."""
        import importlib.util

        if self.requires is None or importlib.util.find_spec(self.requires) is not None:
            return None
        return f"needs the module {self.requires!r}, not installed (pip install 'aaeval[{self.extra}]')"

    def info(self) -> MetricInfo:
        """The description alone, without the function (what a sweep stores)."""
        return MetricInfo(**self.to_dict())

    def applies_to(self, scene) -> bool:
        """False where this metric can say nothing about ``scene``: its mask is always empty
        there, or it needs exact frames of a shaded scene (no exact renderer shades)."""
        from aaeval.metrics.masks import MASKS
        from aaeval.scenes.shaded import has_shaded

        if self.mask is not None and not MASKS.get_entry(self.mask).applies_to(scene):
            return False
        return not ("exact" in self.needs and has_shaded(scene))


#: The functions of the ``image`` metrics, by name (a view kept in step with :data:`METRICS`).
IMAGE_METRICS: dict[str, Callable[..., float]] = {}
#: The functions of the ``temporal`` metrics, by name (a view kept in step with :data:`METRICS`).
TEMPORAL_METRICS: dict[str, Callable[..., float]] = {}
_BY_KIND = {"image": IMAGE_METRICS, "temporal": TEMPORAL_METRICS}


class _MetricRegistry(Registry):
    """The metric registry: it keeps the per-kind views in step."""

    def add(self, name: str, entry: Metric) -> Metric:
        super().add(name, entry)
        _BY_KIND[entry.kind][name] = entry.func
        return entry

    def unregister(self, name: str) -> Metric:
        metric = super().unregister(name)
        _BY_KIND[metric.kind].pop(name, None)
        return metric


#: Every metric, by name, in registration order.
METRICS: Registry = _MetricRegistry("metric", MetricError)


def register_metric(name: str, func: Callable[..., float] | None = None, *, kind: str, title: str, fmt: str,
                    higher_is_better: bool = False, needs: tuple[str, ...] = ("reference",),
                    mask: str | None = None, summary: str | None = None, target: float | None = None,
                    rms: bool = False, requires: str | None = None, extra: str | None = None,
                    by_default: bool = True) -> Metric:
    """Register a metric; the only step needed for compare, sweeps, tables and reports to know it.

    ``register_metric(name, func, ...)`` returns the :class:`Metric`; without ``func`` it is
    a decorator (``@register_metric(name, kind=..., ...)``) returning the function. A metric
    computed by an optional package names the module it imports (``requires``) and the
    optional-dependency group of aaeval that installs it (``extra``): where the module is
    missing it stays listed, as unavailable with that reason, and a config asking for it is
    refused before any work. ``by_default=False``: measured only where named
    (:func:`default_metrics` leaves it out).

    Raises
    ------
    MetricError
        A name registered twice, an unknown kind, need or mask, or a bad format.
    """
    from aaeval.metrics.masks import MASKS

    if func is None:
        return lambda f: register_metric(name, f, kind=kind, title=title, fmt=fmt, higher_is_better=higher_is_better,
                                         needs=needs, mask=mask, summary=summary, target=target, rms=rms,
                                         requires=requires, extra=extra, by_default=by_default).func
    if not isinstance(name, str) or not name.isidentifier():
        raise MetricError(f"metric name must be an identifier (it becomes a table column), got {name!r}")
    if name in METRICS:
        raise MetricError(f"metric {name!r} is registered twice")
    if kind not in KINDS:
        raise MetricError(f"metric {name!r}: kind must be one of {KINDS}, got {kind!r}")
    bad = sorted(set(needs) - set(NEEDS))
    if bad:
        raise MetricError(f"metric {name!r}: unknown need(s) {bad}; needs: {', '.join(NEEDS)}")
    if kind == "temporal" and "frames" not in needs:
        needs = (*needs, "frames")
    if mask is not None:
        if mask not in MASKS:
            raise MetricError(f"metric {name!r}: unknown mask {mask!r}; masks: {', '.join(MASKS)}")
        if "mask" not in _keyword_options(func):
            raise MetricError(f"metric {name!r} declares mask {mask!r} but its function takes no 'mask' option")
        needs = tuple(dict.fromkeys((*needs, "scene")))
    if (requires is None) != (extra is None):
        raise MetricError(f"metric {name!r}: an optional module (requires) and the extra installing it go together")
    try:
        format(1.0, fmt)
    except ValueError:
        raise MetricError(f"metric {name!r}: bad number format {fmt!r}") from None
    doc = (inspect.getdoc(func) or "").split("\n", 1)[0]
    metric = Metric(name=name, func=func, kind=kind, title=title, fmt=fmt, higher_is_better=bool(higher_is_better),
                    needs=tuple(needs), mask=mask, summary=summary or doc,
                    target=None if target is None else float(target), rms=bool(rms), requires=requires, extra=extra,
                    by_default=bool(by_default))
    return METRICS.add(name, metric)


def default_metrics(kind: str, scenes=None) -> tuple[str, ...]:
    """What is measured where no metrics of ``kind`` are named (a sweep group, a comparison):
    every registered ``kind`` metric measured by default (``by_default``), available on this
    machine, and able to say something about at least one of ``scenes``
    (:meth:`Metric.applies_to`; every scene when ``scenes`` is None), in registration order."""
    scenes = None if scenes is None else list(scenes)
    return tuple(name for name, metric in METRICS.items()
                 if metric.kind == kind and metric.by_default and metric.unavailable() is None
                 and (scenes is None or any(metric.applies_to(scene) for scene in scenes)))


def get_metric(name: str, kind: str | None = None) -> Metric:
    """The registered metric ``name`` (of ``kind`` when given); :class:`MetricError` names the choices."""
    metric = METRICS.get(name)
    if metric is None or (kind is not None and metric.kind != kind):
        choices = [n for n, m in METRICS.items() if kind is None or m.kind == kind]
        what = f"{kind} metric" if kind else "metric"
        raise MetricError(f"unknown {what} {name!r}; available: {', '.join(choices)}")
    return metric


def check_metric_names(names, kind: str) -> tuple[str, ...]:
    """The names as a tuple after checking each is a registered ``kind`` metric, given once."""
    names = tuple(names)
    unknown = [n for n in names if n not in METRICS or METRICS[n].kind != kind]
    if unknown:
        choices = [n for n, m in METRICS.items() if m.kind == kind]
        raise MetricError(f"unknown {kind} metric(s) {unknown}; available: {', '.join(choices)}")
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise MetricError(f"metric(s) {repeated} given more than once")
    missing = {n: METRICS[n].unavailable() for n in names}
    missing = {n: why for n, why in missing.items() if why}
    if missing:
        raise MetricError("metric(s) unavailable here: " + "; ".join(f"{n} {why}" for n, why in missing.items()))
    return names


def compute_metric(name: str, image_true, image_test, **context: Any) -> float:
    """Compute the image metric ``name`` of ``image_test`` against ``image_true``.

    Parameters
    ----------
    name : str
        A key of :data:`IMAGE_METRICS`.
    image_true, image_test : ndarray, shape (H, W, 3)
        Reference and test images.
    **context
        Options for the metrics. Each metric receives only the ones it accepts (``mask``
        reaches the masked metrics alone, ``data_range`` reaches ``psnr`` and ``ssim``), so
        one context can serve every metric; an option no metric accepts is an error.

    Returns
    -------
    value : float
    """
    return _dispatch(IMAGE_METRICS, "image", name, image_true, image_test, context)


def compute_temporal_metric(name: str, frames_true, frames_test, **context: Any) -> float:
    """Compute the temporal metric ``name`` (a key of :data:`TEMPORAL_METRICS`) over frames.

    Options are passed as in :func:`compute_metric`.
    """
    return _dispatch(TEMPORAL_METRICS, "temporal", name, frames_true, frames_test, context)


@functools.lru_cache(maxsize=None)  # every metric call reads every function's signature
def _keyword_options(func: Callable) -> dict[str, inspect.Parameter]:
    params = inspect.signature(func).parameters.values()
    return {p.name: p for p in params if p.kind is inspect.Parameter.KEYWORD_ONLY}


def _dispatch(registry: Mapping[str, Callable], kind: str, name: str, true, test, context) -> float:
    get_metric(name, kind)  # the one unknown-name check
    known = set().union(*(_keyword_options(f) for f in registry.values()))
    unknown = sorted(set(context) - known)
    if unknown:
        raise MetricError(
            f"unknown {kind} metric option(s) {unknown}; options: {', '.join(sorted(known)) or 'none'}"
        )
    accepted = _keyword_options(registry[name])
    missing = sorted(k for k, p in accepted.items() if p.default is inspect.Parameter.empty and k not in context)
    if missing:
        raise MetricError(f"{kind} metric {name!r} needs option(s) {missing}")
    return float(registry[name](true, test, **{k: v for k, v in context.items() if k in accepted}))


# --- the built-in metrics -------------------------------------------------------------
register_metric("rmse", rmse, kind="image", title="RMSE", fmt=".3e", rms=True,
                summary="root-mean-square error over pixels and channels")
register_metric("psnr", psnr, kind="image", title="PSNR dB", fmt=".2f", higher_is_better=True,
                summary="peak signal-to-noise ratio, data range 1 (scikit-image)")
register_metric("ssim", ssim, kind="image", title="SSIM", fmt=".4f", higher_is_better=True,
                summary="mean structural similarity, 7x7 uniform window, data range 1 (scikit-image)")
register_metric("ciede2000_mean", ciede2000_mean, kind="image", title="ΔE00 mean", fmt=".3f",
                summary="mean CIEDE2000 colour difference (colour-science)")
register_metric("ciede2000_p95", ciede2000_p95, kind="image", title="ΔE00 p95", fmt=".3f",
                summary="95th percentile of the CIEDE2000 colour difference")
register_metric("flip", flip, kind="image", title="FLIP", fmt=".4f",
                summary="mean LDR-FLIP error (flip-evaluator)")
register_metric("edge_rmse", edge_rmse, kind="image", title="edge RMSE", fmt=".3e", mask="edge", rms=True,
                summary="RMSE over the pixels a visible edge crosses (exact coverage)")
register_metric("highlight_rmse", highlight_rmse, kind="image", title="hl RMSE", fmt=".3e", mask="highlight",
                rms=True,
                summary="RMSE over the highlight pixels (ground-truth specular term > 0.02)")
register_metric("highlight_energy_bias", highlight_energy_bias, kind="image", title="hl bias", fmt="+.3f",
                mask="highlight", target=0.0,
                summary="sum(test) / sum(reference) - 1 over the highlight pixels, RGB (negative: dimmer)")
# Over the frames of an animation. Each error splits into its bias (the time-average,
# which stays with the object) and its flicker (what is left, frame to frame).
register_metric("sum_variation", sum_variation, kind="temporal", title="sum var", fmt=".3e",
                needs=("frames",),
                summary="(max - min) / mean of the test's intensity sums over the frames (no reference)")
register_metric("sum_bias", sum_bias, kind="temporal", title="sum bias (typical frame)", fmt="+.2%",
                needs=("frames", "exact"), target=0.0,
                summary="median over frames of sum(test) / exact sum - 1 (exact: Catmull's area sampling)")
register_metric("temporal_bias", temporal_bias, kind="temporal", title="bias (time-avg error)", fmt=".3e",
                summary="RMS over pixels of the error's time-average (bias**2 + flicker**2 = MSE of all frames)")
register_metric("flicker", flicker, kind="temporal", title="flicker (error minus its time-avg)", fmt=".3e",
                summary="RMS over pixels of the std over frames of the error against the reference")
register_metric("image_flicker", image_flicker, kind="temporal", title="image flicker (interior)", fmt=".3e",
                mask="interior", needs=("frames",),
                summary="RMS over the scene's interior of the test image's own std over frames (no reference)")
register_metric("highlight_bias", highlight_bias, kind="temporal", title="hl bias (time-avg energy)", fmt="+.3f",
                mask="highlight", target=0.0,
                summary="mean over frames of sum(test) / sum(reference) - 1 over each frame's highlight pixels")
register_metric("highlight_energy_flicker", highlight_energy_flicker, kind="temporal",
                title="hl flicker (energy, frame to frame)", fmt=".3e", mask="highlight",
                summary="std over frames of the highlight energy ratio test / reference (what is left after hl bias)")
register_metric("highlight_profile_flicker", highlight_profile_flicker, kind="temporal",
                title="hl flicker (per cross-section)", fmt=".3e", mask="highlight",
                summary="energy per cross-section of each highlight (cut across its own direction): change over frames "
                        "left after each cross-section's steady gain, relative to its energy")
register_metric("highlight_flicker", highlight_flicker, kind="temporal", title="hl change error", fmt=".3e",
                mask="highlight",
                summary="RMS of the frame-to-frame change of the error over the highlight pixels (a moving bias counts)")
# Perceptual: how visible the difference is, popping weighed above a steady error of one size.
register_metric("cvvdp", cvvdp, kind="temporal", title="ColorVideoVDP JOD", fmt=".3f", higher_is_better=True,
                requires=CVVDP_MODULE, extra="cvvdp", by_default=False,  # a neural model: asked for by name
                summary="ColorVideoVDP (Mantiuk et al. 2024) in JOD, 10: indistinguishable from the reference; "
                        "sRGB on a 4K 30-inch monitor at 30 frames per second")
