"""Experiment configs (TOML): groups of scenes x method specs x options x frames.

A config file looks like::

    [experiment]
    name = "edges"
    reference = "catmull"                  # method spec every cell is compared against
    metrics = ["rmse", "psnr"]             # per-frame metrics (see `aaeval metrics`); left out:
                                           # every registered metric that applies to a group's scenes
    temporal = ["sum_variation", "flicker"]  # metrics over the frames of an animation (left out: every
                                           # applicable one, for groups that animate)
    repeats = 1                            # timed renders per cell (groups may override)
    primary = "rmse"                       # the error axis of the report's charts

    [[groups]]
    name = "edge-aliasing"
    scenes = ["../scenes/edges.toml", {generator = "fan", difficulty = [2, 4, 8]}]
    methods = ["point", "supersample", "mitsuba:sampler=stratified"]
    frames = "all"                         # or a list of frame numbers
    options = { spp = [16, 64] }           # expanded for every method that declares it
    options.supersample = { k = [2, 4] }   # for one method only
    metrics = ["rmse", "highlight_rmse"]   # a group may override metrics, temporal, reference
    repeats = 5                            # timed renders per cell, after one untimed warm-up (default 1)

``[experiment].max_seconds`` (default: ``AAEVAL_MAX_SECONDS``, else 600) is the time limit of
one cell or reference, all its repeats: past it the cell is stopped and recorded as failed
("timed out"), and a rerun tries it again.

A method with a ``cache`` option (Mitsuba) gets ``cache=false`` unless the spec sets it, so
its render time is a render, not a cache hit. References keep their cache.

Every key is checked before any work starts; an error names the file and the key. A
config that repeats itself (a scene, a difficulty or a method spec given twice in a group)
is refused, naming the key: every cell of a config is one row of the results table.
Scene paths are relative to the config file.
"""

from __future__ import annotations

import math

import hashlib
import itertools
import json
from collections import Counter
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, Mapping

from aaeval._toml import read_toml, refuse_unknown_keys
from aaeval.catmull import MAX_THREADS
from aaeval.scenes.generate import GENERATORS, generate_scene
from aaeval.metrics import MetricError, check_metric_names
from aaeval.renderers import MethodError, MethodSpec, parse_spec
from aaeval.scenes import Scene, SceneError, parse_scene

__all__ = ["ConfigError", "Experiment", "Group", "SceneSource", "Cell", "SpeedPass", "load_experiment",
           "parse_experiment", "reference_for", "applicable_metrics", "SPEED_MIN_PIXELS"]


class ConfigError(ValueError):
    """An experiment config breaks a rule; the message names the file and the key."""


@dataclass(frozen=True)
class SceneSource:
    """One scene of a group: a file, or a generator at one difficulty."""

    name: str  # shown in tables: file stem, or "fan@8"
    document: Mapping[str, Any]  # parsed TOML, what the scene is made of
    source: str  # file path or generator spec, for messages
    difficulty: float | None = None
    difficulty_label: str | None = None

    @cached_property
    def digest(self) -> str:
        """Hash of the scene's content (not its path): the reference cache key uses it."""
        blob = json.dumps(self.document, sort_keys=True, separators=(",", ":")).encode()
        return hashlib.sha256(blob).hexdigest()

    @cached_property
    def parsed(self) -> Scene:
        """The parsed scene, parsed once (raises :class:`SceneError`)."""
        return parse_scene(self.document, source=self.source)

    @property
    def frames(self) -> int:
        return self.parsed.frames


@dataclass(frozen=True)
class Cell:
    """One unit of work: one scene frame rendered by one method, compared with the reference."""

    group: str
    scene_source: SceneSource  # the scene's document and name (a CellRecord's ``scene`` is its name)
    spec: MethodSpec  # parsed where the config was read; a canonical spec string
    frame: int
    reference: MethodSpec  # the same for the reference
    metrics: tuple[str, ...]
    repeats: int = 1

    def identity(self) -> dict:
        """Everything the row depends on, apart from the code version.

        The group, the scene's name and difficulty are part of it: two config entries that
        happen to build the same scene (a generator clamping two difficulties to one
        radius) stay two rows, each with its own label, never one row counted twice.
        """
        source = self.scene_source
        return {"group": self.group, "scene_name": source.name, "difficulty": source.difficulty,
                "scene": source.digest, "frame": self.frame, "method": self.spec,
                "reference": self.reference, "metrics": sorted(self.metrics), "repeats": self.repeats}


@dataclass(frozen=True)
class Group:
    name: str
    scenes: tuple[SceneSource, ...]
    specs: tuple[MethodSpec, ...]
    frames: Any  # "all" or tuple of ints
    reference: MethodSpec
    metrics: tuple[str, ...]
    repeats: int = 1
    temporal: tuple[str, ...] = ()  # temporal metrics of this group's animations

    def cells(self) -> list[Cell]:
        out = []
        for src in self.scenes:
            frames = range(src.frames) if self.frames == "all" else self.frames
            for spec in self.specs:
                reference = reference_for(spec, self.reference)
                for k in frames:
                    out.append(Cell(self.name, src, spec, int(k), reference, self.metrics, self.repeats))
        return out


def reference_for(spec: MethodSpec, reference: MethodSpec) -> MethodSpec:
    """The reference a cell of ``spec`` is judged against: ``reference`` through the same
    pixel filter as the method (``catmull:filter=tent`` against ``mitsuba:filter=tent``).

    A method renders the image its filter defines; judging it against another filter's
    image measures the filters' difference, not the method. A reference that takes no
    ``filter`` option, or a method without one (the box), leaves ``reference`` as given.
    """
    wanted = spec.options.get("filter", "box")
    if "filter" not in reference.method.options or reference.options.get("filter", "box") == wanted:
        return reference
    return reference.with_options(filter=wanted)


@dataclass(frozen=True)
class SpeedPass:
    """One ``[[speed]]`` table: scenes x method specs timed in the sweep's speed pass (one
    worker, ``threads`` threads, ``repeats`` interleaved rounds after a warm-up), frame 0.
    ``accuracy``: the group whose errors the speed-accuracy chart pairs with these times."""

    scenes: tuple[SceneSource, ...]
    specs: tuple[MethodSpec, ...]
    repeats: int = 5
    threads: int = 1
    accuracy: str | None = None


@dataclass(frozen=True)
class Experiment:
    name: str
    description: str
    path: str
    text: str  # the config file as written, kept with the results
    groups: tuple[Group, ...]
    temporal: tuple[str, ...]
    primary: str
    noise_estimate: bool = True
    fail_above: float | None = None  # a cell whose primary error exceeds this counts as failed
    speed: tuple[SpeedPass, ...] = ()  # the speed pass: the only times the report charts
    max_seconds: float | None = None  # a cell's time limit (None: AAEVAL_MAX_SECONDS or 600)

    def cells(self) -> list[Cell]:
        return [cell for group in self.groups for cell in group.cells()]


_EXPERIMENT_KEYS = {"name", "description", "reference", "metrics", "temporal", "primary", "noise_estimate",
                    "fail_above", "repeats", "max_seconds"}
_GROUP_KEYS = {"name", "scenes", "methods", "frames", "options", "reference", "metrics", "temporal", "animate",
               "repeats"}
_SPEED_KEYS = {"scenes", "methods", "options", "repeats", "threads", "accuracy"}
#: The speed pass times images of at least this many pixels (below, a render is call overhead).
SPEED_MIN_PIXELS = 256 * 256


def load_experiment(path: str | Path) -> Experiment:
    """Read and validate an experiment config; :class:`ConfigError` names file and key."""
    path = Path(path)
    document, text = read_toml(path, ConfigError, "experiment config")
    return parse_experiment(document, path=path, text=text)


def parse_experiment(document: Mapping[str, Any], *, path: str | Path = "<config>", text: str = "") -> Experiment:
    where = str(path)
    base = Path(path).parent if str(path) != "<config>" else Path.cwd()
    unknown = sorted(set(document) - {"experiment", "groups", "speed"})
    if unknown:
        raise ConfigError(f"{where}: unknown top-level key(s) {unknown}; allowed: ['experiment', 'groups', 'speed']")
    head = document.get("experiment")
    if not isinstance(head, Mapping):
        raise ConfigError(f"{where}: missing table [experiment]")
    _no_unknown(head, _EXPERIMENT_KEYS, f"{where}: [experiment]")
    name = _string(head, "name", f"{where}: [experiment]", default=Path(where).stem)
    reference = _spec(_string(head, "reference", f"{where}: [experiment]"), f"{where}: [experiment].reference")
    # None: a group names none and measures every registered metric that applies to its scenes
    metrics = _metric_list(head["metrics"], f"{where}: [experiment].metrics", temporal=False) \
        if "metrics" in head else None
    temporal = _metric_list(head["temporal"], f"{where}: [experiment].temporal", temporal=True) \
        if "temporal" in head else None
    primary = _string(head, "primary", f"{where}: [experiment]", default=metrics[0] if metrics else "rmse")
    repeats = _repeats(head.get("repeats", 1), f"{where}: [experiment].repeats")
    noise = head.get("noise_estimate", True)
    if not isinstance(noise, bool):
        raise ConfigError(f"{where}: [experiment].noise_estimate must be true or false, got {noise!r}")

    fail_above = head.get("fail_above")
    if fail_above is not None and (isinstance(fail_above, bool) or not isinstance(fail_above, (int, float))
                                   or not math.isfinite(fail_above) or fail_above <= 0):  # nan never compares above
        raise ConfigError(f"{where}: [experiment].fail_above must be a finite positive number, got {fail_above!r}")

    max_seconds = head.get("max_seconds")
    if max_seconds is not None and (isinstance(max_seconds, bool) or not isinstance(max_seconds, (int, float))
                                    or not 0 < max_seconds <= MAX_CELL_SECONDS):
        raise ConfigError(f"{where}: [experiment].max_seconds must be a number of seconds above 0 and at most "
                          f"{MAX_CELL_SECONDS:g} (a day), got {max_seconds!r}")

    raw_groups = document.get("groups")
    if not isinstance(raw_groups, list) or not raw_groups:
        raise ConfigError(f"{where}: needs at least one [[groups]] table")
    groups = []
    for i, raw in enumerate(raw_groups):
        groups.append(_group(raw, f"{where}: groups[{i}]", base, reference, metrics, repeats, temporal))
    temporal = tuple(dict.fromkeys(m for g in groups for m in g.temporal))
    _check_cell_count(groups, where)
    for i, g in enumerate(groups):  # a cell no run would finish is refused now, not stopped at its limit
        _check_speed_budget(g.scenes, g.specs, g.repeats, f"{where}: groups[{i}]", max_seconds, what="cell")
    names = [g.name for g in groups]
    dup = sorted(n for n, k in Counter(names).items() if k > 1)
    if dup:
        raise ConfigError(f"{where}: groups.name must be unique, repeated: {dup}")
    if not any(primary in g.metrics for g in groups):
        raise ConfigError(f"{where}: [experiment].primary {primary!r} is not a metric of any group")
    raw_speed = document.get("speed", [])
    if not isinstance(raw_speed, list):
        raise ConfigError(f"{where}: speed must be an array of [[speed]] tables")
    speed = tuple(_speed(raw, f"{where}: speed[{i}]", base, set(names), max_seconds)
                  for i, raw in enumerate(raw_speed))
    return Experiment(name, str(head.get("description", "")), where, text, tuple(groups), temporal, primary, noise,
                      None if fail_above is None else float(fail_above), speed,
                      None if max_seconds is None else float(max_seconds))


def _check_cell_count(groups: list, where: str) -> None:
    """Refuse a config of more than :data:`MAX_CELLS` cells, counted before any is built."""
    total = 0
    for g in groups:
        per_spec = sum(src.frames if g.frames == "all" else len(g.frames) for src in g.scenes)
        total += per_spec * len(g.specs)
    if total > MAX_CELLS:
        raise ConfigError(f"{where}: {total} cells (groups x scenes x method specs x frames), over the limit of "
                          f"{MAX_CELLS}; at even 0.1 s a cell that is {total * 0.1 / 3600:.3g} hours (split the "
                          "config or give fewer frames)")


def _speed(raw: Any, where: str, base: Path, groups: set[str], limit: float | None = None) -> SpeedPass:
    """One ``[[speed]]`` table: ``scenes``, ``methods``, ``options`` as in a group; ``repeats``
    (interleaved rounds, default 5), ``threads`` (default 1: given to every method that has a
    ``threads`` option) and ``accuracy`` (a group name)."""
    if not isinstance(raw, Mapping):
        raise ConfigError(f"{where}: must be a table")
    _no_unknown(raw, _SPEED_KEYS, where)
    scenes = _scenes(raw.get("scenes"), f"{where}.scenes", base)
    for src in scenes:
        if src.parsed.width * src.parsed.height < SPEED_MIN_PIXELS:
            raise ConfigError(f"{where}.scenes: {src.name} is {src.parsed.width}x{src.parsed.height}; the speed pass "
                              f"times images of at least {SPEED_MIN_PIXELS} pixels (256 x 256)")
    methods, options = _methods_and_options(raw, where)
    repeats = _repeats(raw.get("repeats", 5), f"{where}.repeats")
    threads = raw.get("threads", 1)
    if isinstance(threads, bool) or not isinstance(threads, int) or not 1 <= threads <= MAX_THREADS:
        raise ConfigError(f"{where}.threads: expected a whole number of threads from 1 to {MAX_THREADS}, "
                          f"got {threads!r}")
    specs = []
    for spec, given in _expand_specs(methods, options, where, with_given=True):
        if "threads" in spec.method.options and "threads" not in given:
            spec = spec.with_options(threads=threads)
        specs.append(spec)
    _check_speed_budget(scenes, specs, repeats, where, limit)
    accuracy = raw.get("accuracy")
    if accuracy is not None and accuracy not in groups:
        raise ConfigError(f"{where}.accuracy: {accuracy!r} is not a group of this experiment ({sorted(groups)})")
    return SpeedPass(scenes, tuple(specs), repeats, threads, accuracy)


def _check_speed_budget(scenes, specs, repeats: int, where: str, limit: float | None, what: str = "speed") -> None:
    """Each render of a cell or the speed pass, with its warm-up and ``repeats`` rounds,
    estimated (the render budget's own estimate) against the time limit of one task: a size
    no run would finish is refused now, with the estimate, not when it is stopped."""
    from aaeval.sweeps.executors import task_limit
    from aaeval.renderers.budget import check_budget
    from aaeval.renderers.cost import render_seconds
    from aaeval.renderers.registry import MethodError

    limit_s = task_limit(limit)
    for src in scenes:
        for spec in specs:
            try:  # the render's own budget (samples, memory, time), as `aaeval render` applies it
                check_budget(src.parsed, spec.method, spec.options)
            except MethodError as exc:
                raise ConfigError(f"{where}: {spec}: {exc}") from None
            try:
                seconds = render_seconds(src.parsed, spec.method, spec.options) * (repeats + 1)
            except Exception:  # noqa: BLE001 - a method's own estimate failing: no estimate, the run decides
                continue
            if seconds > limit_s:
                raise ConfigError(f"{where}: {spec} on {src.name} ({src.parsed.width}x{src.parsed.height}) x "
                                  f"{repeats + 1} renders would take about {seconds:.3g} s, over the limit of "
                                  f"{limit_s:g} s (max_seconds or AAEVAL_MAX_SECONDS; a smaller scene or fewer "
                                  "repeats)")


def _methods_and_options(raw: Mapping, where: str) -> tuple[list, Mapping]:
    """A table's ``methods`` (a non-empty list of specs) and ``options`` (option = [values])."""
    methods = raw.get("methods")
    if not isinstance(methods, list) or not methods or not all(isinstance(m, str) for m in methods):
        raise ConfigError(f"{where}.methods: expected a non-empty list of method specs, got {methods!r}")
    options = raw.get("options", {})
    if not isinstance(options, Mapping):
        raise ConfigError(f"{where}.options: expected a table of option = [values], got {options!r}")
    return methods, options


def _group(raw: Any, where: str, base: Path, reference: MethodSpec, metrics: tuple[str, ...] | None, repeats: int,
           temporal: tuple[str, ...] | None) -> Group:
    if not isinstance(raw, Mapping):
        raise ConfigError(f"{where}: must be a table")
    _no_unknown(raw, _GROUP_KEYS, where)
    name = _string(raw, "name", where)
    if "reference" in raw:
        reference = _spec(_string(raw, "reference", where), f"{where}.reference")
    if "metrics" in raw:
        metrics = _metric_list(raw["metrics"], f"{where}.metrics", temporal=False)
    if "temporal" in raw:
        temporal = _metric_list(raw["temporal"], f"{where}.temporal", temporal=True)
    scenes = _scenes(raw.get("scenes"), f"{where}.scenes", base)
    if "animate" in raw:
        scenes = _animate(scenes, raw["animate"], f"{where}.animate")
    if metrics is None:
        metrics = applicable_metrics(scenes, "image")
    if temporal is None:
        temporal = applicable_metrics(scenes, "temporal") if any(src.frames > 1 for src in scenes) else ()
    methods, options = _methods_and_options(raw, where)
    specs = _expand_specs(methods, options, f"{where}")
    frames = _frames(raw.get("frames", "all"), f"{where}.frames", scenes)
    if "repeats" in raw:
        repeats = _repeats(raw["repeats"], f"{where}.repeats")
    return Group(name, scenes, tuple(specs), frames, reference, metrics, repeats, temporal)


#: The longest list of frame numbers a group may give: the most frames a scene may have
#: (``aaeval.scenes.generate``'s frame limit).
MAX_FRAME_LIST = 100_000
#: The most steps of one generator's difficulty ladder; LEVEL_SECONDS is about what one
#: step costs at parse time (generate and check its scene), for the estimate in the refusal.
MAX_LADDER = 1000
LEVEL_SECONDS = 0.01
#: The most cells one config may plan: every cell is a record, a row and a render.
MAX_CELLS = 200_000

#: The largest per-cell time limit a config may set (a day): above it, no limit at all.
MAX_CELL_SECONDS = 86400.0

#: More timed renders per cell than any timing needs: a typo such as 1e9 would run for days.
MAX_REPEATS = 1000


def _repeats(raw: Any, where: str) -> int:
    if isinstance(raw, bool) or not isinstance(raw, int) or not 1 <= raw <= MAX_REPEATS:
        raise ConfigError(f"{where}: expected a whole number of timed renders from 1 to {MAX_REPEATS}, "
                          f"got {raw!r}")
    return raw


def _expand_specs(methods: list[str], options: Mapping[str, Any], where: str,
                  with_given: bool = False) -> list:
    """Each method spec times the option values it takes (values given in the spec win),
    parsed: the config's specs enter here. With ``with_given``, pairs of the spec and the
    option names its text set.

    ``options = { k = [2, 4] }`` applies to every method that declares ``k``;
    ``options.supersample = { k = [2, 4] }`` to ``supersample`` only.
    """
    shared = {k: v for k, v in options.items() if not isinstance(v, Mapping)}
    scoped = {k: v for k, v in options.items() if isinstance(v, Mapping)}
    bases = [_base_spec(text, f"{where}.methods[{j}]") for j, text in enumerate(methods)]
    by_name = {base.name: base.method for base, _ in bases}
    for name, table in scoped.items():
        if name not in by_name:
            raise ConfigError(f"{where}.options.{name}: {name!r} is not one of this group's methods {sorted(by_name)}")
        bad = sorted(set(table) - set(by_name[name].options))
        if bad:
            raise ConfigError(f"{where}.options.{name}: method {name!r} has no option(s) {bad}; "
                              f"options: {', '.join(sorted(by_name[name].options)) or 'none'}")
    used: set[str] = set()
    specs: list[MethodSpec] = []
    given_of: dict[str, set] = {}
    for j, (base, given) in enumerate(bases):
        mine = {k: v for k, v in shared.items() if k in base.method.options}
        used.update(mine)
        mine.update(scoped.get(base.name, {}))
        axes = [k for k in sorted(mine) if k not in given]
        values = []
        for key in axes:
            vals = mine[key] if isinstance(mine[key], list) else [mine[key]]
            if not vals:
                raise ConfigError(f"{where}.options.{key}: empty list of values")
            values.append(vals)
        for combo in itertools.product(*values):
            try:
                spec = base.with_options(**dict(zip(axes, combo)))
            except MethodError as exc:
                raise ConfigError(f"{where}.options: {exc}") from None
            if spec in specs:
                raise ConfigError(f"{where}.methods[{j}]: method {spec!r} is already in this group "
                                  "(given twice, or made twice by options); give each method once")
            specs.append(spec)
            given_of[spec] = given | set(axes)
    unused = sorted(set(shared) - used)
    if unused:
        raise ConfigError(f"{where}.options: option(s) {unused} are declared by none of the methods {methods}")
    return [(spec, given_of[spec]) for spec in specs] if with_given else specs


def _base_spec(text: str, where: str) -> tuple[MethodSpec, set[str]]:
    """The spec a config's text names, read once, and the option names the text set; a
    method with a ``cache`` option renders for real unless the text says otherwise (a cache
    hit would be timed as the render)."""
    try:
        name, raw = parse_spec(text)
        spec = MethodSpec.of(name, raw)
    except MethodError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    given = set(raw)
    if "cache" in spec.method.options and "cache" not in given:
        spec, given = spec.with_options(cache=False), given | {"cache"}
    return spec, given


def _scenes(raw: Any, where: str, base: Path) -> tuple[SceneSource, ...]:
    if not isinstance(raw, list) or not raw:
        raise ConfigError(f"{where}: expected a non-empty list of scene files or generator tables, got {raw!r}")
    out: list[SceneSource] = []
    for i, item in enumerate(raw):
        here = f"{where}[{i}]"
        if isinstance(item, str):
            out.append(_scene_file(item, here, base))
        elif isinstance(item, Mapping) and "generator" in item:
            out.extend(_generated(item, here))
        elif isinstance(item, Mapping) and "path" in item:
            _no_unknown(item, {"path", "difficulty", "difficulty_label"}, here)
            src = _scene_file(item["path"], here, base)
            d = item.get("difficulty")
            if d is not None and (isinstance(d, bool) or not isinstance(d, (int, float))):
                raise ConfigError(f"{here}.difficulty: expected a number, got {d!r}")
            labelled = SceneSource(src.name, src.document, src.source, None if d is None else float(d),
                                   item.get("difficulty_label", "difficulty"))
            labelled.__dict__["parsed"] = src.parsed  # same document: parsed once
            out.append(labelled)
        else:
            raise ConfigError(f"{here}: expected a scene path, {{path = ...}} or {{generator = ...}}, got {item!r}")
    seen: dict[tuple, int] = {}
    for i, src in enumerate(out):
        label = (src.name, src.difficulty)
        if label in seen:
            raise ConfigError(f"{where}: scene {src.name!r} (from {src.source}) is listed twice in this group; "
                              "give each scene once, or give one a different name")
        seen[label] = i
    return tuple(out)


def _scene_file(rel: Any, where: str, base: Path) -> SceneSource:
    if not isinstance(rel, str):
        raise ConfigError(f"{where}: expected a scene file path, got {rel!r}")
    candidates = [base / rel, Path(rel)]
    path = next((p for p in candidates if p.is_file()), None)
    if path is None:
        raise ConfigError(f"{where}: scene file {rel!r} not found (looked at {', '.join(map(str, candidates))})")
    try:
        document, _ = read_toml(path, SceneError, "scene file")
        src = SceneSource(path.stem, document, str(path))
        src.parsed  # noqa: B018 - parse (and validate) now, once
    except SceneError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    return src


def _generated(item: Mapping[str, Any], where: str) -> list[SceneSource]:
    name = item["generator"]
    if name not in GENERATORS:
        raise ConfigError(f"{where}.generator: unknown generator {name!r}; available: {', '.join(sorted(GENERATORS))}")
    levels = item.get("difficulty")
    if isinstance(levels, list) and len(levels) > MAX_LADDER:  # each level is a scene generated and parsed now
        raise ConfigError(f"{where}.difficulty: a ladder of {len(levels)} steps, over the limit of {MAX_LADDER}: "
                          f"each step is a scene generated and checked before the sweep starts (about "
                          f"{len(levels) * LEVEL_SECONDS:.0f} s for these alone) and a row of every chart")
    if not isinstance(levels, list) or not levels:
        raise ConfigError(f"{where}.difficulty: expected a non-empty list of difficulty values, got {_brief(levels)}")
    params = {k: v for k, v in item.items() if k not in ("generator", "difficulty")}
    out = []
    try:
        counts = Counter(levels)
    except TypeError:  # an unhashable value (a table): refused as not a number below
        counts = Counter()
    repeated = sorted((d for d, n in counts.items() if n > 1), key=str)
    if repeated:
        raise ConfigError(f"{where}.difficulty: value(s) {_brief(repeated)} given more than once")
    for d in levels:
        if isinstance(d, bool) or not isinstance(d, (int, float)):
            raise ConfigError(f"{where}.difficulty: expected numbers, got {d!r}")
        extra = "".join(f",{k}={params[k]}" for k in sorted(params))
        try:
            document = generate_scene(name, d, **params)
            src = SceneSource(f"{name}@{d:g}", document, f"generator {name}(difficulty={d}{extra})",
                              float(d), GENERATORS[name].difficulty)
            src.parsed  # noqa: B018 - parse (and validate) now, once
        except (ValueError, TypeError) as exc:
            raise ConfigError(f"{where}: {exc}") from None
        out.append(src)
    return out


def applicable_metrics(scenes, kind: str) -> tuple[str, ...]:
    """Every registered ``kind`` metric that can say something about at least one of
    ``scenes`` (:meth:`aaeval.metrics.Metric.applies_to`), in registration order: what a
    group measures when neither it nor the experiment names its metrics."""
    from aaeval.metrics import METRICS

    return tuple(name for name, metric in METRICS.items()
                 if metric.kind == kind and any(metric.applies_to(src.parsed) for src in scenes))


def _animate(scenes: tuple[SceneSource, ...], raw: Any, where: str) -> tuple[SceneSource, ...]:
    """Give every scene of the group this [animation] table (static scenes set moving)."""
    if not isinstance(raw, Mapping):
        raise ConfigError(f"{where}: expected a table {{frames = N, translate = [dx, dy], phases = \"r2\"}}, "
                          f"got {raw!r}")
    _no_unknown(raw, {"frames", "translate", "phases", "seed"}, where)
    out = []
    for src in scenes:
        document = {**src.document, "animation": dict(raw)}
        moving = SceneSource(src.name, document, src.source, src.difficulty, src.difficulty_label)
        try:
            moving.__dict__["parsed"] = parse_scene(document, source=f"{src.source} with {where}")
        except SceneError as exc:
            raise ConfigError(f"{where}: {exc}") from None
        out.append(moving)
    return tuple(out)


def _frames(raw: Any, where: str, scenes: tuple[SceneSource, ...]) -> Any:
    if raw == "all":
        from aaeval.renderers.budget import check_frames

        for src in scenes:  # a file's [animation] frames is budgeted as a generator's
            try:
                check_frames(src.parsed, src.frames, f"{where} = \"all\"")
            except SceneError as exc:
                raise ConfigError(str(exc)) from None
        return "all"
    if isinstance(raw, list) and len(raw) > MAX_FRAME_LIST:  # before any pass over it, and never echoed
        raise ConfigError(f"{where}: a list of {len(raw)} frame numbers, over the limit of {MAX_FRAME_LIST} "
                          "(the most frames a scene may have; use \"all\")")
    if not isinstance(raw, list) or not raw or not all(isinstance(k, int) and not isinstance(k, bool) for k in raw):
        raise ConfigError(f"{where}: expected \"all\" or a non-empty list of frame numbers, got {_brief(raw)}")
    # repeats by counting once (list.count per item was quadratic: 50 s for 60k frames)
    repeated = sorted(k for k, n in Counter(raw).items() if n > 1)
    if repeated:
        raise ConfigError(f"{where}: frame(s) {_brief(repeated)} given more than once")
    for src in scenes:
        n = src.frames
        bad = [k for k in raw if not 0 <= k < n]
        if bad:
            raise ConfigError(f"{where}: frame(s) {_brief(bad)} outside 0..{n - 1} of scene {src.source}")
    return tuple(raw)


def _brief(values: Any, limit: int = 10) -> str:
    """A list shown by its first ``limit`` items and its length: an error line must stay
    readable when a config holds a million values."""
    if isinstance(values, (list, tuple)) and len(values) > limit:
        return f"[{', '.join(repr(v)[:40] for v in values[:limit])}, ... ({len(values)} in all)]"
    text = repr(values)
    return text if len(text) <= 200 else text[:200] + "..."


def _spec(spec: str, where: str) -> MethodSpec:
    try:
        return MethodSpec.parse(spec)
    except MethodError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def _metric_list(raw: Any, where: str, *, temporal: bool) -> tuple[str, ...]:
    if not isinstance(raw, list) or not all(isinstance(m, str) for m in raw) or (not temporal and not raw):
        raise ConfigError(f"{where}: expected a {'' if temporal else 'non-empty '}list of metric names, got {raw!r}")
    try:
        return check_metric_names(raw, "temporal" if temporal else "image")
    except MetricError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def _string(table: Mapping, key: str, where: str, default: str | None = None) -> str:
    if key not in table:
        if default is not None:
            return default
        raise ConfigError(f"{where}: missing required key '{key}'")
    value = table[key]
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(f"{where}.{key}: expected a non-empty string, got {value!r}")
    return value


def _no_unknown(table: Mapping, allowed: set[str], where: str) -> None:
    refuse_unknown_keys(table, allowed, where, ConfigError)

