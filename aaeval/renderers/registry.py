"""One registry of rendering methods, addressed by a spec string.

A method is a plain function ``render(scene, **options) -> ndarray (H, W, 3)`` registered
under a name with its declared options (Mitsuba-plugin style). A *spec* names a method
and sets options: ``"catmull"``, ``"supersample:k=4"``, ``"mitsuba:spp=4096,seed=1"``.
:func:`resolve` validates the name and every option (type, range, rule) and fails loudly on
anything unknown. Before any render, :func:`check_budget` refuses a request whose point
samples, memory or time cannot fit (see ``MAX_SAMPLES``, :func:`available_memory` and
``MAX_SECONDS``), with its estimate, instead of running out of memory or time half-way.

Memory and time are estimated from the scene in one pass over its polygons' bounding boxes
(:func:`scene_load`): ``pairs``, the polygon pairs whose boxes overlap (every method that
draws polygons first resolves near depth ties between such pairs, and Weiler-Atherton
clips them against each other), and ``depth_squares``, the sum over pixels of the squared
number of boxes over the pixel (a per-pixel sort of fragments, as the A-buffer's, costs
that). A method declares what it costs per unit once, in its ``register_method`` call
(``memory=``, ``seconds=``); the pass over the boxes costs O(polygons + pixels / cell).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from aaeval.options import Option, OptionError, Registry
from aaeval.scenes import Scene
from aaeval.scenes.shaded import has_shaded

__all__ = [
    "METHODS",
    "Method",
    "MethodSpec",
    "INCIDENTAL_OPTIONS",
    "Option",
    "MethodError",
    "MethodFailure",
    "check_image",
    "register_method",
    "parse_spec",
    "format_spec",
    "resolve",
    "render",
    "render_timed",
    "warm_up",
    "required_table",
    "check_budget",
    "available_memory",
    "MAX_SAMPLES",
    "MAX_SECONDS",
    "SceneLoad",
    "check_frames",
    "scene_load",
]

# Point samples (pixels x samples per pixel) one render may take: 2^36, about ten minutes
# of point sampling at ~10 ns per sample; AAEVAL_MAX_SAMPLES raises or lowers it.
MAX_SAMPLES = 1 << 36
# A float64 RGB image is held about this many times over by a render and its writing
# (the result, accumulators, the conversion for the file); measured methods add their own.
IMAGE_COPIES = 4
# Estimated seconds one render may take (methods that declare ``seconds=``); as long as the
# point-sample limit takes; AAEVAL_MAX_SECONDS raises or lowers it.
MAX_SECONDS = 600.0
# Every method that draws the polygons first groups near depth ties among polygons whose
# boxes overlap (aaeval.weiler_atherton.near_ties through catmull.kernel_inputs): per such
# pair, bytes held and seconds taken. Measured on 2000 and 4000 identical triangles in a
# 16x16 image (every pair overlapping): about 210 bytes and 1 microsecond per pair (and
# Weiler-Atherton on 1e4 of them: 11 GB, 44 s, i.e. 226 bytes and 0.9 us per pair in all).
PAIR_BYTES = 200
PAIR_SECONDS = 0.8e-6


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
    # whether it draws the scene's polygons itself (and so runs the near-tie pass over them);
    # False for one that hands the scene to another renderer (Mitsuba)
    draws_polygons: bool = True
    # the method whose speed-pass time this one's is reported against (a peer drawing the same
    # scenes), or None
    speed_baseline: str | None = None


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
    draws_polygons: bool = True,
    speed_baseline: str | None = None,
):
    """Register ``render(scene, **options)`` under ``name``: ``register_method(name, render, ...)``
    or, as a decorator, ``@register_method(name, ...)``; a name registered twice is refused.

    ``samples(options)`` (point samples per pixel), ``memory(scene, options)`` (bytes
    beyond the image) and ``seconds(scene, options)`` (the render's estimated time) let
    :func:`check_budget` refuse requests that cannot fit; :func:`scene_load` gives the
    counts an estimate is built from.
    """

    def decorate(func):
        METHODS.add(name, Method(name, func, dict(options or {}), summary, exact, warmup, requires, samples, memory,
                                 seconds, draws_polygons, speed_baseline))
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


#: Specs parsed in this process, by their text (a method registered again is parsed anew).
_PARSED: dict[str, "MethodSpec"] = {}


class MethodSpec(str):
    """A method spec parsed and validated once: the canonical spec string, carrying the
    :class:`Method` it names (``.method``) and its full options, defaults filled in
    (``.options``, read-only).

    Make one with :meth:`parse` where a spec enters (the command line, a sweep config, a
    stored table) and pass it down: nothing below parses it again. It *is* its canonical
    string (the options that differ from the defaults, sorted: ``"catmull"`` and
    ``"catmull:specular=none"`` are both ``"catmull"``), so records, tables and stores
    keep plain strings; :meth:`label` is the one rule for the label shown to a reader.
    """

    method: Method
    options: Mapping[str, Any]

    @classmethod
    def parse(cls, spec: str, **overrides: Any) -> "MethodSpec":
        """The spec ``spec`` names (a string, or a MethodSpec returned as is), with
        ``overrides`` set; :class:`MethodError` (one line) for an unknown method, an
        unknown option or a value the option does not take."""
        if isinstance(spec, MethodSpec) and not overrides:
            return spec
        if not overrides:  # a spec's text is parsed once a process (the config, the table, a worker)
            known = _PARSED.get(str(spec))
            if known is not None and METHODS.get(known.method.name) is known.method:
                return known
        name, raw = parse_spec(str(spec))
        parsed = cls.of(name, {**raw, **overrides})
        if not overrides:
            _PARSED[str(spec)] = parsed  # the text as written, beside the canonical text
        return parsed

    @classmethod
    def of(cls, name: str, options: Mapping[str, Any]) -> "MethodSpec":
        """The spec of method ``name`` with ``options`` set (raw strings from a spec's text,
        as :func:`parse_spec` splits it, or values), checked as :meth:`parse` checks them."""
        method = METHODS.get(name)
        if method is None:
            raise MethodError(_unknown_method(name))
        defaults = {key: opt.default for key, opt in method.options.items()}
        return cls._checked(method, defaults, options)

    @classmethod
    def _checked(cls, method: Method, base: Mapping[str, Any], raw: Mapping[str, Any]) -> "MethodSpec":
        """``base`` (checked options) with ``raw`` converted and set: one :class:`MethodError`
        line for an unknown option or a value the option does not take."""
        name = method.name
        unknown = sorted(set(raw) - set(method.options))
        if unknown:
            allowed = ", ".join(sorted(method.options)) or "none"
            raise MethodError(f"method {name!r}: unknown option(s) {unknown}; options: {allowed}")
        options = dict(base)
        for key, value in raw.items():
            options[key] = method.options[key].convert(value, f"method {name!r} option {key!r}", MethodError)
        return cls._made(method, options)

    @classmethod
    def _made(cls, method: Method, options: Mapping[str, Any]) -> "MethodSpec":
        made = str.__new__(cls, _spec_text(method, options, shown=_differs))
        made.method = method
        made.options = MappingProxyType(dict(options))
        # its canonical text, as records and tables store it, needs no parsing again
        known = _PARSED.get(str(made))
        if known is None or known.method is not method:
            _PARSED[str(made)] = made
        return made

    @property
    def name(self) -> str:
        return self.method.name

    def with_options(self, **changes: Any) -> "MethodSpec":
        """This spec with ``changes`` set (checked as :meth:`parse` checks them)."""
        # the spec is parsed already: only the changes are checked (its text is not read again)
        return MethodSpec._checked(self.method, self.options, changes) if changes else self

    def label(self, keep: Iterable[str] = ()) -> str:
        """What a reader is shown: the method and the options that differ from their
        defaults, plus those named in ``keep`` (the ones that vary among the rows shown
        together), sorted; options that only say how a result was obtained
        (:data:`INCIDENTAL_OPTIONS`) are left out."""
        keep = set(keep)
        return _spec_text(self.method, self.options,
                          shown=lambda m, k, v: k not in INCIDENTAL_OPTIONS and (k in keep or _differs(m, k, v)))

    def __copy__(self) -> "MethodSpec":
        return self  # a value: nothing in it changes

    def __deepcopy__(self, memo) -> "MethodSpec":
        return self

    def __reduce__(self):
        # another process parses the string again (methods are functions, not data)
        return (_spec_from_text, (str(self),))


def _unknown_method(name: str) -> str:
    if not METHODS:  # nothing registered: the program never loaded the registries
        return (f"unknown method {name!r}: no method is registered in this process "
                "(call aaeval.registries.load() first)")
    return f"unknown method {name!r}; available: {', '.join(sorted(METHODS))}"


def _spec_from_text(text: str) -> MethodSpec | str:
    """A spec unpickled in another process: parsed there, or left a string when that
    process does not know the method (a worker without a plugin), so that the task that
    renders it fails with the MethodError, as a result, instead of the transfer."""
    try:
        return MethodSpec.parse(text)
    except MethodError:
        return text


#: Options that only say how a result was obtained, not what was rendered (left out of labels).
INCIDENTAL_OPTIONS = frozenset({"cache"})


def _differs(method: Method, key: str, value: Any) -> bool:
    return key not in method.options or method.options[key].default != value


def _spec_text(method: Method, options: Mapping[str, Any], shown: Callable[[Method, str, Any], bool]) -> str:
    keys = sorted(k for k, v in options.items() if shown(method, k, v))
    return method.name + "".join(f"{':' if i == 0 else ','}{k}={options[k]}" for i, k in enumerate(keys))


def resolve(spec: str, **overrides: Any) -> tuple[Method, dict[str, Any]]:
    """The method a spec names and its full, validated options (defaults filled in):
    :meth:`MethodSpec.parse`, unpacked."""
    parsed = MethodSpec.parse(spec, **overrides)
    return parsed.method, dict(parsed.options)


def format_spec(name: str, options: Mapping[str, Any]) -> str:
    """Canonical spec string of method ``name`` with ``options``: the :class:`MethodSpec`'s."""
    return MethodSpec.of(name, options)


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
    headroom = _address_space_headroom()
    if headroom is not None:  # ulimit -v: past it an allocation fails however much RAM is free
        avail = min(avail, headroom)
    limit = os.environ.get("AAEVAL_MAX_MEMORY")
    if limit:
        avail = min(avail, _bytes(limit, "AAEVAL_MAX_MEMORY"))
    return avail


def _address_space_headroom() -> int | None:
    """Bytes of address space left under ``RLIMIT_AS`` (its soft limit less this process's
    ``VmSize``), or None when there is no such limit."""
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, AttributeError, OSError, ValueError):
        return None
    if soft == resource.RLIM_INFINITY or soft < 0:
        return None
    used = 0
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    used = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError):
        pass
    return max(0, soft - used)


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


def _max_seconds() -> float:
    text = os.environ.get("AAEVAL_MAX_SECONDS")
    if not text:
        return MAX_SECONDS
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value > 0:
        raise MethodError(f"AAEVAL_MAX_SECONDS={text!r}: expected a positive number of seconds")
    return value


@dataclass(frozen=True)
class SceneLoad:
    """What a scene costs to draw, from its polygons' bounding boxes (:func:`scene_load`)."""

    polygons: int
    vertices: int
    # polygon pairs whose boxes overlap (inside the image); estimated from a sample when large
    pairs: float
    # sum over pixels of (boxes over the pixel)^2, and of boxes over the pixel
    depth_squares: float
    fragments: float


# exact pair counts up to this many polygons; beyond, a sample of polygons against all
_EXACT_PAIRS = 2048
_PAIR_WORK = 1 << 22  # box comparisons the pair estimate may make (tens of milliseconds)
_GRID_CELLS = 1 << 18  # cells of the depth grid


def scene_load(scene: Scene) -> SceneLoad:
    """Counts of :class:`SceneLoad` for ``scene`` (boxes clipped to the image), computed
    once per scene object."""
    cached = scene.__dict__.get("_aaeval_scene_load")
    if cached is None:
        cached = _scene_load(scene)
        scene.__dict__["_aaeval_scene_load"] = cached  # a frozen dataclass: its cache, as cached_property's
    return cached


def _scene_load(scene: Scene) -> SceneLoad:
    polys = scene.polygons
    n = len(polys)
    if n == 0:
        return SceneLoad(0, 0, 0.0, 0.0, 0.0)
    arr = scene.arrays
    xy = arr.vertices[:, :2]
    lo = np.minimum.reduceat(xy, arr.start, axis=0)
    hi = np.maximum.reduceat(xy, arr.start, axis=0)
    extent = np.array([scene.width, scene.height], dtype=np.float64)
    keep = np.all((lo < extent) & (hi > 0), axis=1)  # boxes reaching into the image
    lo, hi = np.clip(lo, 0.0, extent), np.clip(hi, 0.0, extent)
    lo, hi = lo[keep], hi[keep]
    m = len(lo)
    # pairs: every pair when few, else each sampled box against all, scaled
    if m <= _EXACT_PAIRS:
        sample = np.arange(m)
    else:
        size = int(min(m, max(64, _PAIR_WORK // m)))
        sample = np.random.default_rng(0).choice(m, size=size, replace=False)
    hits = 0
    step = max(1, (1 << 22) // (4 * max(m, 1)))
    for a in range(0, len(sample), step):
        s = sample[a : a + step]
        over = ((lo[s, None, 0] <= hi[None, :, 0]) & (lo[None, :, 0] <= hi[s, None, 0])
                & (lo[s, None, 1] <= hi[None, :, 1]) & (lo[None, :, 1] <= hi[s, None, 1]))
        hits += int(over.sum()) - len(s)  # not with itself
    pairs = hits / 2 * (m / max(len(sample), 1))
    # depth per grid cell: boxes over it (a cell of c x c pixels counts a box touching it)
    c = max(1, math.ceil(math.sqrt(scene.width * scene.height / _GRID_CELLS)))
    gw, gh = -(-scene.width // c), -(-scene.height // c)
    x0 = np.clip(np.floor(lo[:, 0] / c).astype(np.int64), 0, gw - 1)
    y0 = np.clip(np.floor(lo[:, 1] / c).astype(np.int64), 0, gh - 1)
    x1 = np.clip(np.ceil(hi[:, 0] / c).astype(np.int64), x0 + 1, gw)
    y1 = np.clip(np.ceil(hi[:, 1] / c).astype(np.int64), y0 + 1, gh)
    diff = np.zeros((gh + 1, gw + 1), np.int64)
    np.add.at(diff, (y0, x0), 1)
    np.add.at(diff, (y0, x1), -1)
    np.add.at(diff, (y1, x0), -1)
    np.add.at(diff, (y1, x1), 1)
    depth = np.cumsum(np.cumsum(diff, axis=0), axis=1)[:gh, :gw].astype(np.float64)
    return SceneLoad(n, len(arr.vertices), float(pairs), float((depth**2).sum() * c * c),
                     float(depth.sum() * c * c))


# The least one render costs whatever the scene: Python's call, the budget check, the image
# (seconds per render and per pixel; measured 0.5-0.8 ms of CPU per frame for point, abuffer
# and catmull on a 25x1 scene); a run of many frames is budgeted with at least this.
RENDER_SECONDS = 1e-3
PIXEL_SECONDS = 1e-8


def render_seconds(scene: Scene, method: Method, options: Mapping[str, Any]) -> float:
    """The estimated seconds of one render (the near-tie pass, the method's own estimate,
    and the least any render costs)."""
    seconds = RENDER_SECONDS + PIXEL_SECONDS * scene.width * scene.height
    if _draws_polygons(method):
        seconds += PAIR_SECONDS * scene_load(scene).pairs
    if method.seconds is not None:
        seconds += float(method.seconds(scene, options))
    return seconds


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
    limit_s = _max_seconds()
    if seconds > limit_s:
        times = f" x {repeats} repeats" if repeats != 1 else ""
        raise SceneError(f"{scene.source}: {where}: {frames} frames x {len(specs)} method(s){times} would take about "
                         f"{seconds:.3g} s, over the limit of {limit_s:.3g} s (AAEVAL_MAX_SECONDS raises it; "
                         "or render fewer frames)")
    need = total * 3 * 8 * held
    have = available_memory()
    if need > have:
        raise SceneError(f"{scene.source}: {where}: keeping {held} image(s) of {frames} frames needs about "
                         f"{need / 2**30:.3g} GiB of memory, {have / 2**30:.3g} GiB available "
                         "(AAEVAL_MAX_MEMORY may lower it; or render fewer frames)")


def _draws_polygons(method: Method) -> bool:
    # methods drawing a source table (resvg, freetype) or handing the scene to another
    # renderer (Mitsuba) do not run the near-tie pass over the polygons
    return method.requires is None and method.draws_polygons


def check_budget(scene: Scene, method: Method, options: Mapping[str, Any]) -> None:
    """Refuse, with the estimate, a render whose samples, memory or time cannot fit."""
    pixels = scene.width * scene.height
    where = f"{scene.source}: method {method.name!r} on a {scene.width}x{scene.height} image"
    if method.samples is not None:
        per_pixel = int(method.samples(options))
        limit = _max_samples()
        if pixels * per_pixel > limit:
            raise MethodError(f"{where} at {per_pixel:.4g} samples per pixel takes {pixels * per_pixel:.3g} point "
                              f"samples, over the limit of {limit:.3g} (AAEVAL_MAX_SAMPLES)")
    load = scene_load(scene) if (_draws_polygons(method) or method.seconds is not None) else None
    pair_bytes = PAIR_BYTES * load.pairs if load is not None and _draws_polygons(method) else 0.0
    need = pixels * 3 * 8 * IMAGE_COPIES + pair_bytes + (float(method.memory(scene, options)) if method.memory else 0)
    have = available_memory()
    if need > have:
        detail = f", {load.pairs:.3g} overlapping polygon pairs" if load is not None and load.pairs > 1e5 else ""
        raise MethodError(f"{where} needs about {need / 2**30:.3g} GiB of memory ({len(scene.polygons)} polygons"
                          f"{detail}), {have / 2**30:.3g} GiB available (AAEVAL_MAX_MEMORY may lower it)")
    seconds = render_seconds(scene, method, options)
    limit_s = _max_seconds()
    if seconds > limit_s:
        detail = f", {load.pairs:.3g} overlapping polygon pairs" if load is not None else ""
        raise MethodError(f"{where} would take about {seconds:.3g} s ({len(scene.polygons)} polygons{detail}), "
                          f"over the limit of {limit_s:.3g} s (AAEVAL_MAX_SECONDS raises it)")


class MethodFailure(MethodError):
    """A method that raised, or returned something that is not an image of its scene: one
    line naming the method and the rule (an input error of the plugin, exit 2 from the CLI;
    a failed row in compare and sweeps)."""


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    detail = text[0][:300] if text else ""
    return f"{type(exc).__name__}{': ' + detail if detail else ''}"


# Far above any radiance a scene here holds, far below where a squared error or an
# image's sum overflows float64 (a -1e300 image would make every error metric infinite).
MAX_PIXEL_MAGNITUDE = 1e100


def check_image(name: str, image, shape: tuple[int, int, int]) -> np.ndarray:
    """The rules every method's result follows: an ndarray of real floats, the scene's
    ``(H, W, 3)``, every value finite and within
    :data:`MAX_PIXEL_MAGNITUDE`. Returns ``image``; :class:`MethodFailure` otherwise."""
    where = f"method {name!r}"
    if not isinstance(image, np.ndarray):
        raise MethodFailure(f"{where} returned {type(image).__name__}, expected a numpy array of shape {shape}")
    if image.dtype.kind != "f":
        raise MethodFailure(f"{where} returned dtype {image.dtype}, expected real floats (float64 linear RGB)")
    if image.shape != shape:
        raise MethodFailure(f"{where} returned shape {image.shape}, expected {shape}")
    if not image.size:
        return image
    # the extremes alone (a NaN among the values is the extremes' NaN): no temporary image
    lo, hi = float(image.min()), float(image.max())
    if not (math.isfinite(lo) and math.isfinite(hi)):
        bad = int(np.count_nonzero(~np.isfinite(image)))
        raise MethodFailure(f"{where} returned {bad} value(s) that are NaN or infinite; every value must be finite")
    if max(-lo, hi) > MAX_PIXEL_MAGNITUDE:
        raise MethodFailure(f"{where} returned a value of magnitude {max(-lo, hi):.3g}; every value "
                            f"must be within +-{MAX_PIXEL_MAGNITUDE:g} (so that errors and sums stay finite)")
    return image


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
