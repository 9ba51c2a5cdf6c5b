"""The render budget: refuse, before any render, a request whose point samples, memory or
time cannot fit, with its estimate, instead of running out of memory or time half-way.

The limits are ``MAX_SAMPLES`` (``AAEVAL_MAX_SAMPLES``), the memory this process may use
(:func:`aaeval.limits.available_memory`, ``AAEVAL_MAX_MEMORY``) and ``MAX_SECONDS``
(``AAEVAL_MAX_SECONDS``), read through the package's one parser of environment limits
(:mod:`aaeval.limits`); the estimates are the method's declared costs and the scene's
(:mod:`aaeval.renderers.cost`).
"""

from __future__ import annotations

from typing import Any, Mapping

from aaeval.limits import available_memory, env_number, env_seconds
from aaeval.renderers.cost import PAIR_BYTES, render_seconds, scene_load
from aaeval.renderers.registry import Method, MethodError
from aaeval.renderers.spec import MethodSpec
from aaeval.scenes import Scene

__all__ = ["IMAGE_COPIES", "MAX_SAMPLES", "MAX_SECONDS", "check_budget", "check_frames"]

# Point samples (pixels x samples per pixel) one render may take: 2^36, about ten minutes
# of point sampling at ~10 ns per sample; AAEVAL_MAX_SAMPLES raises or lowers it.
MAX_SAMPLES = 1 << 36
# A float64 RGB image is held about this many times over by a render and its writing
# (the result, accumulators, the conversion for the file); measured methods add their own.
IMAGE_COPIES = 4
# Estimated seconds one render may take (methods that declare ``seconds=``); as long as the
# point-sample limit takes; AAEVAL_MAX_SECONDS raises or lowers it.
MAX_SECONDS = 600.0


def check_frames(scene: Scene, frames: int, where: str, specs: tuple[str | MethodSpec, ...] = (),
                 held: int = 0, repeats: int = 1) -> None:
    """Refuse rendering ``frames`` frames of ``scene`` when the pixels over all of them
    exceed the limit generated scenes have (``aaeval.scenes.generate.MAX_PIXEL_FRAMES``):
    a scene file's ``[animation] frames`` is budgeted as a generator's is. With ``specs``
    (the methods rendering every frame, each ``repeats`` times: an upper bound where one
    of them, a reference, renders once), the whole run's estimated time must fit
    ``AAEVAL_MAX_SECONDS`` too, and ``held`` images of every frame kept at once (compare
    keeps each method's frames for the temporal metrics) must fit in memory."""
    from aaeval.scenes import SceneError
    from aaeval.scenes.generate import MAX_PIXEL_FRAMES

    frames = int(frames)
    total = scene.width * scene.height * frames
    if total > MAX_PIXEL_FRAMES:
        raise SceneError(f"{scene.source}: {where}: {frames} frames of {scene.width}x{scene.height} are "
                         f"{total:.3g} pixels, over the limit of {MAX_PIXEL_FRAMES:.3g} pixels over all frames "
                         "(render fewer frames)")
    if not specs:
        return
    parsed = [MethodSpec.parse(spec) for spec in specs]
    # as floats: a count of any size gives a time (an int past float's range would overflow)
    seconds = sum(render_seconds(scene, spec.method, spec.options) for spec in parsed) * float(frames) * float(repeats)
    limit_s = env_seconds("AAEVAL_MAX_SECONDS", MAX_SECONDS, MethodError)
    if seconds > limit_s:
        times = f" x {repeats} repeats" if repeats != 1 else ""
        raise SceneError(f"{scene.source}: {where}: {frames} frames x {len(specs)} method(s){times} would take about "
                         f"{seconds:.3g} s, over the limit of {limit_s:.3g} s (AAEVAL_MAX_SECONDS raises it; "
                         "or render fewer frames)")
    need = total * 3 * 8 * held
    have = available_memory(MethodError)
    if need > have:
        raise SceneError(f"{scene.source}: {where}: keeping {held} image(s) of {frames} frames needs about "
                         f"{need / 2**30:.3g} GiB of memory, {have / 2**30:.3g} GiB available "
                         "(AAEVAL_MAX_MEMORY may lower it; or render fewer frames)")


def check_budget(scene: Scene, method: Method, options: Mapping[str, Any]) -> None:
    """Refuse a scene the method must not draw (:attr:`Method.check`), then, with the
    estimate, a render whose samples, memory or time cannot fit."""
    if method.check is not None:
        method.check(scene, options)
    pixels = scene.width * scene.height
    where = f"{scene.source}: method {method.name!r} on a {scene.width}x{scene.height} image"
    if method.samples is not None:
        per_pixel = int(method.samples(options))
        limit = int(env_number("AAEVAL_MAX_SAMPLES", MAX_SAMPLES, MethodError))
        if pixels * per_pixel > limit:
            raise MethodError(f"{where} at {per_pixel:.4g} samples per pixel takes {pixels * per_pixel:.3g} point "
                              f"samples, over the limit of {limit:.3g} (AAEVAL_MAX_SAMPLES)")
    load = scene_load(scene) if (method.runs_near_ties or method.seconds is not None) else None
    pair_bytes = PAIR_BYTES * load.pairs if load is not None and method.runs_near_ties else 0.0
    need = pixels * 3 * 8 * IMAGE_COPIES + pair_bytes + (float(method.memory(scene, options)) if method.memory else 0)
    have = available_memory(MethodError)
    if need > have:
        detail = f", {load.pairs:.3g} overlapping polygon pairs" if load is not None and load.pairs > 1e5 else ""
        raise MethodError(f"{where} needs about {need / 2**30:.3g} GiB of memory ({len(scene.polygons)} polygons"
                          f"{detail}), {have / 2**30:.3g} GiB available (AAEVAL_MAX_MEMORY may lower it)")
    seconds = render_seconds(scene, method, options)
    limit_s = env_seconds("AAEVAL_MAX_SECONDS", MAX_SECONDS, MethodError)
    if seconds > limit_s:
        detail = f", {load.pairs:.3g} overlapping polygon pairs" if load is not None else ""
        raise MethodError(f"{where} would take about {seconds:.3g} s ({len(scene.polygons)} polygons{detail}), "
                          f"over the limit of {limit_s:.3g} s (AAEVAL_MAX_SECONDS raises it)")

