"""The timed run: render a scene with the method a spec names, after its budget check and
its warm-up, timing the method's call alone and checking the image it returns.

:func:`render_timed` is the one path: :func:`render` is its image, :func:`warm_up` its
untimed rehearsal of a spec at an image size.
"""

from __future__ import annotations

import time

import numpy as np

from aaeval.renderers.budget import check_budget
from aaeval.renderers.check import MethodFailure, check_image
from aaeval.renderers.registry import Method
from aaeval.renderers.spec import MethodSpec
from aaeval.scenes import Scene
from aaeval.scenes.shaded import has_shaded

__all__ = ["render", "render_timed", "warm_up"]


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    detail = text[0][:300] if text else ""
    return f"{type(exc).__name__}{': ' + detail if detail else ''}"



# The one warm-up cache of this process: a method's name once its own warm-up
# (``Method.warmup``) ran, and (spec, width, height, shaded) once that spec was rendered
# untimed at that size (:func:`warm_up`).
_warmed: set = set()


def render(scene: Scene, spec: str | MethodSpec, *, frame: int | None = None) -> np.ndarray:
    """Render ``scene`` (at ``frame`` if given) with the method ``spec`` names (a
    :class:`MethodSpec`, or a string parsed here): the image of :func:`render_timed`."""
    return render_timed(scene, spec, frame=frame)[0]


def render_timed(scene: Scene, spec: str | MethodSpec, *, frame: int | None = None, repeats: int = 1,
                 rehearse: bool = False) -> tuple[np.ndarray, list[float]]:
    """Render ``repeats`` times, each timed; return the last image and every render's seconds.

    The budget is checked once, before anything runs (:func:`check_budget`: a refusal
    costs nothing). Then the warm-up, untimed and once per process: the method's own
    (:attr:`Method.warmup`), or with ``rehearse`` the spec itself at this image size
    (:func:`warm_up`; a method's warm-up compiles its default path only, while
    ``catmull:filter=tent`` compiles kernels of its own). Each image is checked
    (:func:`check_image`) after its clock stops.
    """
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"repeats must be a whole number >= 1, got {repeats!r}")
    spec = MethodSpec.parse(spec)
    if frame is not None:
        scene = scene.at_frame(frame)
    check_budget(scene, spec.method, spec.options)
    if rehearse:
        _rehearse(scene, spec)
    else:
        _warm_method(spec.method)
    seconds = []
    for _ in range(repeats):
        image, elapsed = _timed(scene, spec)
        seconds.append(elapsed)
    return image, seconds


def warm_up(scene: Scene, spec: str | MethodSpec, *, frame: int | None = None) -> bool:
    """One untimed render of ``spec`` on ``scene`` the first time this process meets (spec,
    width, height, shaded or flat), after the budget check; True if it rendered.

    The spec is rendered as it will be timed, every option included: Dr.Jit compiles per
    sample count and image size, and options such as ``filter=tent`` or
    ``specular=crow`` compile kernels of their own.
    """
    spec = MethodSpec.parse(spec)
    if frame is not None:
        scene = scene.at_frame(frame)
    check_budget(scene, spec.method, spec.options)
    return _rehearse(scene, spec)


def _rehearse(scene: Scene, spec: MethodSpec) -> bool:
    """:func:`warm_up` past its budget check."""
    key = (str(spec), scene.width, scene.height, has_shaded(scene))
    if key in _warmed:
        return False
    _warm_method(spec.method)
    _timed(scene, spec)
    _warmed.add(key)
    return True


def _warm_method(method: Method) -> None:
    """The method's own warm-up, once per process."""
    if method.name in _warmed:
        return
    if method.warmup is not None:
        try:
            method.warmup()
        except (Exception, RecursionError, SystemExit, GeneratorExit) as exc:  # noqa: BLE001
            raise MethodFailure(f"method {method.name!r} failed in its warm-up: {_first_line(exc)}") from None
    _warmed.add(method.name)


def _timed(scene: Scene, spec: MethodSpec) -> tuple[np.ndarray, float]:
    """One render and its seconds (the method's call alone); the image checked after."""
    method = spec.method
    start = time.perf_counter()
    try:
        image = method.render(scene, **dict(spec.options))
    except ValueError:  # a method's own input error (an option the scene cannot take): one line already
        raise
    # a method's sys.exit() or a stray GeneratorExit is its failure too, not the command's
    # exit (sys.exit(3) in a plugin made `aaeval render` exit 3 with nothing said); only an
    # interrupt (Ctrl-C, SIGTERM, the sweep's time limit) passes through
    except (Exception, RecursionError, SystemExit, GeneratorExit) as exc:  # noqa: BLE001
        raise MethodFailure(f"method {method.name!r} failed: {_first_line(exc)}") from None
    seconds = time.perf_counter() - start
    return check_image(method.name, image, scene.shape), seconds
