"""One registry of rendering methods, addressed by a spec string.

A method is a plain function ``render(scene, **options) -> ndarray (H, W, 3)`` registered
under a name with its declared options (Mitsuba-plugin style). A *spec* names a method
and sets options: ``"catmull"``, ``"supersample:k=4"``, ``"mitsuba:spp=4096,seed=1"``.
:func:`resolve` validates the name and every option and fails loudly on anything unknown.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

import numpy as np

from aaeval.scenes import Scene

__all__ = [
    "METHODS",
    "Method",
    "Option",
    "MethodError",
    "register_method",
    "parse_spec",
    "format_spec",
    "resolve",
    "render",
    "render_timed",
    "required_table",
]


class MethodError(ValueError):
    """An unknown method name, or an unknown or malformed option in a spec."""


@dataclass(frozen=True)
class Option:
    """A declared option of a method: its type, default and meaning."""

    type: type
    default: Any
    doc: str = ""
    choices: tuple | None = None
    minimum: float | None = None

    def convert(self, raw: Any, where: str) -> Any:
        value = _coerce(raw, self.type, where)
        if self.choices is not None and value not in self.choices:
            raise MethodError(f"{where}: {value!r} is not one of {list(self.choices)}")
        if self.minimum is not None and value < self.minimum:
            raise MethodError(f"{where}: must be >= {self.minimum}, got {value!r}")
        return value


def _coerce(raw: Any, kind: type, where: str) -> Any:
    if not isinstance(raw, str):
        if kind is float and isinstance(raw, int) and not isinstance(raw, bool):
            return float(raw)
        if isinstance(raw, kind) and not (kind is int and isinstance(raw, bool)):
            return raw
        raise MethodError(f"{where}: expected {kind.__name__}, got {raw!r}")
    try:
        if kind is bool:
            if raw.lower() in ("1", "true", "yes", "on"):
                return True
            if raw.lower() in ("0", "false", "no", "off"):
                return False
            raise ValueError(raw)
        return kind(raw)
    except ValueError:
        raise MethodError(f"{where}: expected {kind.__name__}, got {raw!r}") from None


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


METHODS: dict[str, Method] = {}


def register_method(
    name: str,
    *,
    summary: str,
    options: Mapping[str, Option] | None = None,
    exact: bool = False,
    warmup: Callable[[], None] | None = None,
    requires: str | None = None,
):
    """Decorator registering ``render(scene, **options)`` under ``name``."""

    def decorate(func):
        if name in METHODS:
            raise ValueError(f"method {name!r} is registered twice")
        METHODS[name] = Method(name, func, dict(options or {}), summary, exact, warmup, requires)
        return func

    return decorate


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


def parse_spec(spec: str) -> tuple[str, dict[str, str]]:
    """Split ``"name:key=value,key=value"`` into the name and raw option strings."""
    if not isinstance(spec, str) or not spec.strip():
        raise MethodError(f"empty method spec {spec!r}")
    name, _, rest = spec.strip().partition(":")
    options: dict[str, str] = {}
    for item in filter(None, (part.strip() for part in rest.split(","))):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise MethodError(f"method spec {spec!r}: option {item!r} is not key=value")
        if key.strip() in options:
            raise MethodError(f"method spec {spec!r}: option {key.strip()!r} given twice")
        options[key.strip()] = value.strip()
    return name.strip(), options


def resolve(spec: str, **overrides: Any) -> tuple[Method, dict[str, Any]]:
    """The method a spec names and its full, validated options (defaults filled in)."""
    name, raw = parse_spec(spec)
    _load_builtin_methods()
    if name not in METHODS:
        raise MethodError(f"unknown method {name!r}; available: {', '.join(sorted(METHODS))}")
    method = METHODS[name]
    raw = {**raw, **overrides}
    unknown = sorted(set(raw) - set(method.options))
    if unknown:
        allowed = ", ".join(sorted(method.options)) or "none"
        raise MethodError(f"method {name!r}: unknown option(s) {unknown}; options: {allowed}")
    options = {key: opt.default for key, opt in method.options.items()}
    for key, value in raw.items():
        options[key] = method.options[key].convert(value, f"method {name!r} option {key!r}")
    return method, options


def format_spec(name: str, options: Mapping[str, Any]) -> str:
    """Canonical spec string: the options that differ from the defaults, sorted.

    Two specs naming the same rendering give the same string (``"catmull"`` and
    ``"catmull:specular=none"`` both give ``"catmull"``), and labels stay short.
    """
    _load_builtin_methods()
    declared = METHODS[name].options if name in METHODS else {}
    changed = {k: v for k, v in options.items() if k not in declared or declared[k].default != v}
    if not changed:
        return name
    return name + ":" + ",".join(f"{k}={changed[k]}" for k in sorted(changed))


def render(scene: Scene, spec: str, *, frame: int | None = None) -> np.ndarray:
    """Render ``scene`` (at ``frame`` if given) with the method ``spec`` names."""
    method, options = resolve(spec)
    if frame is not None:
        scene = scene.at_frame(frame)
    image = method.render(scene, **options)
    expected = scene.shape
    if image.shape != expected:
        raise RuntimeError(f"method {method.name!r} returned shape {image.shape}, expected {expected}")
    return image


_warmed: set[str] = set()


def render_timed(scene: Scene, spec: str, *, frame: int | None = None) -> tuple[np.ndarray, float]:
    """Render and return ``(image, seconds)``; JIT compilation is done before the clock starts."""
    method, _ = resolve(spec)
    if method.name not in _warmed:
        if method.warmup is not None:
            method.warmup()
        _warmed.add(method.name)
    if frame is not None:
        scene = scene.at_frame(frame)
    start = time.perf_counter()
    image = render(scene, spec)
    return image, time.perf_counter() - start


def _load_builtin_methods() -> None:
    # Importing the package registers every built-in method exactly once.
    import aaeval.renderers  # noqa: F401
