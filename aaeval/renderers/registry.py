"""The one registry of rendering methods: what a method is and how it is registered.

A method is a plain function ``render(scene, **options) -> ndarray (H, W, 3)`` registered
under a name with its declared options (Mitsuba-plugin style) and its properties: whether
it is exact, the scene table it draws from, whether it draws the scene's polygons itself,
and what it costs (``samples=``, ``memory=``, ``seconds=``, read by the render budget,
:mod:`aaeval.renderers.budget`). A spec string names a method and sets its options
(:mod:`aaeval.renderers.spec`); :mod:`aaeval.renderers.run` renders with it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

import numpy as np

from aaeval.options import Option, OptionError, Registry
from aaeval.scenes import Scene

__all__ = ["METHODS", "Method", "MethodError", "Option", "register_method", "required_table"]


class MethodError(OptionError):
    """An unknown method name, or an unknown or malformed option in a spec."""


@dataclass(frozen=True)
class Method:
    """A registered rendering method."""

    name: str
    render: Callable[..., np.ndarray]
    options: Mapping[str, Option] = field(default_factory=dict)
    summary: str = ""
    exact: bool = False
    warmup: Callable[[], None] | None = None
    # the scene extension table the method draws from (e.g. "text"); it refuses scenes without it
    requires: str | None = None
    # point samples per pixel for these options (None: one pass per pixel, no sampling)
    samples: Callable[[Mapping[str, Any]], int] | None = None
    # bytes the method holds besides IMAGE_COPIES images, for a scene and options
    memory: Callable[[Scene, Mapping[str, Any]], int] | None = None
    # estimated seconds of the render, for a scene and options (None: not estimated)
    seconds: Callable[[Scene, Mapping[str, Any]], float] | None = None
    # refuses (MethodError) a scene the method must not draw, before the budget and the clock
    check: Callable[[Scene, Mapping[str, Any]], None] | None = None
    # whether it draws the scene's polygons itself (and so runs the near-tie pass over them);
    # False for one that hands the scene to another renderer (Mitsuba)
    draws_polygons: bool = True
    # the method whose speed-pass time this one's is reported against (a peer drawing the same
    # scenes), or None
    speed_baseline: str | None = None

    @property
    def runs_near_ties(self) -> bool:
        """Whether a render first groups near depth ties among the scene's polygons: only a
        method that draws the polygons itself does; one drawing a source table
        (``requires``: resvg, freetype) or handing the scene to another renderer
        (``draws_polygons=False``: Mitsuba) does not."""
        return self.requires is None and self.draws_polygons


METHODS: Registry = Registry("method", MethodError)


def register_method(
    name: str,
    func: Callable[..., np.ndarray] | None = None,
    *,
    summary: str,
    options: Mapping[str, Option] | None = None,
    exact: bool = False,
    warmup: Callable[[], None] | None = None,
    requires: str | None = None,
    samples: Callable[[Mapping[str, Any]], int] | None = None,
    memory: Callable[[Scene, Mapping[str, Any]], int] | None = None,
    seconds: Callable[[Scene, Mapping[str, Any]], float] | None = None,
    check: Callable[[Scene, Mapping[str, Any]], None] | None = None,
    draws_polygons: bool = True,
    speed_baseline: str | None = None,
):
    """Register ``render(scene, **options)`` under ``name``: ``register_method(name, render, ...)``
    or, as a decorator, ``@register_method(name, ...)``; a name registered twice is refused.

    ``samples(options)`` (point samples per pixel), ``memory(scene, options)`` (bytes
    beyond the image) and ``seconds(scene, options)`` (the render's estimated time) let
    :func:`aaeval.renderers.budget.check_budget` refuse requests that cannot fit;
    :func:`aaeval.renderers.cost.scene_load` gives the counts an estimate is built from.
    ``check(scene, options)``, called there first, refuses a scene the method must not draw
    (raising :class:`MethodError`): work that is no part of the render, so not timed.
    """

    def decorate(func):
        METHODS.add(name, Method(name, func, dict(options or {}), summary, exact, warmup, requires, samples, memory,
                                 seconds, check, draws_polygons, speed_baseline))
        return func

    return decorate if func is None else decorate(func)


def required_table(scene: Scene, name: str) -> Any:
    """The scene's extension table that method ``name`` draws from (``Method.requires``).

    A scene without it is refused in one line: such a method draws the scene's source
    (the text, the SVG), not its polygons.
    """
    table = METHODS[name].requires
    value = scene.extensions.get(table)
    if value is None:
        raise MethodError(
            f"{scene.source}: method {name!r} draws a scene's [{table}] table (written by "
            f"'aaeval import {table}'); this scene has none"
        )
    return value

