"""One registry of rendering methods, addressed by a spec string.

A method is a plain function ``render(scene, **options) -> ndarray (H, W, 3)`` registered
under a name with its declared options (Mitsuba-plugin style). A *spec* names a method
and sets options: ``"catmull"``, ``"supersample:k=4"``, ``"mitsuba:spp=4096,seed=1"``.
:func:`resolve` validates the name and every option (type, range, rule) and fails loudly on
anything unknown. Before any render, :func:`check_budget` refuses a request whose point
samples or memory cannot fit (see ``MAX_SAMPLES`` and :func:`available_memory`), with its
estimate, instead of running out of memory or time half-way.
"""

from __future__ import annotations

import math
import os
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
    "check_budget",
    "available_memory",
    "MAX_SAMPLES",
]

# Point samples (pixels x samples per pixel) one render may take: 2^36, about ten minutes
# of point sampling at ~10 ns per sample; AAEVAL_MAX_SAMPLES raises or lowers it.
MAX_SAMPLES = 1 << 36
# A float64 RGB image is held about this many times over by a render and its writing
# (the result, accumulators, the conversion for the file); measured methods add their own.
IMAGE_COPIES = 4


class MethodError(ValueError):
    """An unknown method name, or an unknown or malformed option in a spec."""


@dataclass(frozen=True)
class Option:
    """A declared option of a method: its type, default and meaning, and the values it takes.

    ``minimum`` and ``maximum`` bound numbers (inclusive); ``check(value)`` returns why a
    value is refused, or None. Float options are always finite.
    """

    type: type
    default: Any
    doc: str = ""
    choices: tuple | None = None
    minimum: float | None = None
    maximum: float | None = None
    check: Callable[[Any], str | None] | None = None

    def convert(self, raw: Any, where: str) -> Any:
        value = _coerce(raw, self.type, where)
        if self.type is float and not math.isfinite(value):
            raise MethodError(f"{where}: must be a finite number, got {raw!r}")
        if self.choices is not None and value not in self.choices:
            raise MethodError(f"{where}: {value!r} is not one of {list(self.choices)}")
        if self.minimum is not None and value < self.minimum:
            raise MethodError(f"{where}: must be >= {self.minimum}, got {value!r}")
        if self.maximum is not None and value > self.maximum:
            raise MethodError(f"{where}: must be <= {self.maximum}, got {value!r}")
        problem = self.check(value) if self.check is not None else None
        if problem:
            raise MethodError(f"{where}: {problem}, got {value!r}")
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
    # point samples per pixel for these options (None: one pass per pixel, no sampling)
    samples: Callable[[Mapping[str, Any]], int] | None = None
    # bytes the method holds besides IMAGE_COPIES images, for a scene and options
    memory: Callable[[Scene, Mapping[str, Any]], int] | None = None


METHODS: dict[str, Method] = {}


def register_method(
    name: str,
    *,
    summary: str,
    options: Mapping[str, Option] | None = None,
    exact: bool = False,
    warmup: Callable[[], None] | None = None,
    requires: str | None = None,
    samples: Callable[[Mapping[str, Any]], int] | None = None,
    memory: Callable[[Scene, Mapping[str, Any]], int] | None = None,
):
    """Decorator registering ``render(scene, **options)`` under ``name``.

    ``samples(options)`` (point samples per pixel) and ``memory(scene, options)`` (bytes
    beyond the image) let :func:`check_budget` refuse requests that cannot fit.
    """

    def decorate(func):
        if name in METHODS:
            raise ValueError(f"method {name!r} is registered twice")
        METHODS[name] = Method(name, func, dict(options or {}), summary, exact, warmup, requires, samples, memory)
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


def available_memory() -> int:
    """Bytes a render may use: MemAvailable, or ``AAEVAL_MAX_MEMORY`` (e.g. ``8G``) if lower."""
    avail = None
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    if avail is None:
        try:
            avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            avail = 1 << 62  # unknown: only AAEVAL_MAX_MEMORY limits
    limit = os.environ.get("AAEVAL_MAX_MEMORY")
    if limit:
        avail = min(avail, _bytes(limit, "AAEVAL_MAX_MEMORY"))
    return avail


def _bytes(text: str, where: str) -> int:
    units = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
    number, unit = text.strip().upper().rstrip("IB"), ""
    if number and number[-1] in units:
        number, unit = number[:-1], number[-1]
    try:
        return int(float(number) * units[unit])
    except ValueError:
        raise MethodError(f"{where}={text!r}: expected bytes such as 8G or 512M") from None


def _max_samples() -> int:
    text = os.environ.get("AAEVAL_MAX_SAMPLES")
    if not text:
        return MAX_SAMPLES
    try:
        return int(float(text))
    except ValueError:
        raise MethodError(f"AAEVAL_MAX_SAMPLES={text!r}: expected a number") from None


def check_budget(scene: Scene, method: Method, options: Mapping[str, Any]) -> None:
    """Refuse, with the estimate, a render whose samples or memory cannot fit."""
    pixels = scene.width * scene.height
    where = f"{scene.source}: method {method.name!r} on a {scene.width}x{scene.height} image"
    if method.samples is not None:
        per_pixel = int(method.samples(options))
        limit = _max_samples()
        if pixels * per_pixel > limit:
            raise MethodError(f"{where} at {per_pixel:.4g} samples per pixel takes {pixels * per_pixel:.3g} point "
                              f"samples, over the limit of {limit:.3g} (AAEVAL_MAX_SAMPLES)")
    need = pixels * 3 * 8 * IMAGE_COPIES + (int(method.memory(scene, options)) if method.memory else 0)
    have = available_memory()
    if need > have:
        raise MethodError(f"{where} needs about {need / 2**30:.3g} GiB of memory, {have / 2**30:.3g} GiB "
                          "available (AAEVAL_MAX_MEMORY may lower it)")


def render(scene: Scene, spec: str, *, frame: int | None = None) -> np.ndarray:
    """Render ``scene`` (at ``frame`` if given) with the method ``spec`` names."""
    method, options = resolve(spec)
    if frame is not None:
        scene = scene.at_frame(frame)
    check_budget(scene, method, options)
    image = method.render(scene, **options)
    expected = scene.shape
    if image.shape != expected:
        raise RuntimeError(f"method {method.name!r} returned shape {image.shape}, expected {expected}")
    return image


_warmed: set[str] = set()


def render_timed(scene: Scene, spec: str, *, frame: int | None = None) -> tuple[np.ndarray, float]:
    """Render and return ``(image, seconds)``; JIT compilation is done before the clock starts."""
    method, options = resolve(spec)
    check_budget(scene, method, options)  # before the warm-up: a refusal costs nothing
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
