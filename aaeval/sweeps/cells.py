"""A config's group and its expansion into cells: scenes x method specs x frames.

A :class:`Group` is one ``[[groups]]`` table read (:func:`read_group`); its
:meth:`~Group.cells` are the units of work, one :class:`Cell` a row of the results. Method
specs are parsed once, here, where their text enters: each spec times the option values the
group's ``options`` give it (:func:`expand_specs`). A group that repeats itself (a method spec
or a frame given twice) is refused, naming the key.
"""

from __future__ import annotations

import itertools
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from aaeval.metrics import default_metrics
from aaeval.renderers import MethodError, MethodSpec, parse_spec
from aaeval.scenes import SceneError
from aaeval.sweeps.config_keys import (GROUP_KEYS, ConfigError, brief, metric_names, method_spec, read_key,
                                       refuse_unknown)
from aaeval.sweeps.scene_sources import SceneSource, animated, read_scenes

__all__ = ["Cell", "Group", "read_group", "expand_specs", "reference_for", "MAX_FRAME_LIST"]

#: The longest list of frame numbers a group may give: the most frames a scene may have
#: (``aaeval.scenes.generate``'s frame limit).
MAX_FRAME_LIST = 100_000


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
    """One ``[[groups]]`` table, read: its scenes, parsed method specs, frames and what a
    cell of it is judged by."""

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


def read_group(raw: Any, where: str, base: Path, reference: MethodSpec, metrics: tuple[str, ...] | None,
               repeats: int, temporal: tuple[str, ...] | None) -> Group:
    """One ``[[groups]]`` table; ``reference``, ``metrics``, ``repeats`` and ``temporal`` are
    the experiment's, which the group's own keys override (None: every applicable metric)."""
    if not isinstance(raw, Mapping):
        raise ConfigError(f"{where}: must be a table")
    refuse_unknown(raw, GROUP_KEYS, where)
    given = {key: read_key(raw, GROUP_KEYS, key, where) for key in GROUP_KEYS}
    if given["reference"] is not None:
        reference = method_spec(given["reference"], f"{where}.reference")
    if given["metrics"] is not None:
        metrics = metric_names(given["metrics"], f"{where}.metrics", temporal=False)
    if given["temporal"] is not None:
        temporal = metric_names(given["temporal"], f"{where}.temporal", temporal=True)
    scenes = read_scenes(given["scenes"], f"{where}.scenes", base)
    if given["animate"] is not None:
        scenes = animated(scenes, given["animate"], f"{where}.animate")
    if metrics is None:
        metrics = default_metrics("image", [src.parsed for src in scenes])
    if temporal is None:
        moving = any(src.frames > 1 for src in scenes)
        temporal = default_metrics("temporal", [src.parsed for src in scenes]) if moving else ()
    specs = expand_specs(given["methods"], given["options"], where)
    frames = _frames(given["frames"], f"{where}.frames", scenes)
    repeats = repeats if given["repeats"] is None else given["repeats"]
    return Group(given["name"], scenes, tuple(specs), frames, reference, metrics, repeats, temporal)


def expand_specs(methods: list[str], options: Mapping[str, Any], where: str,
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
        raise ConfigError(f"{where}: expected \"all\" or a non-empty list of frame numbers, got {brief(raw)}")
    # counted in one pass: a list of 100,000 frames is checked at once
    repeated = sorted(k for k, n in Counter(raw).items() if n > 1)
    if repeated:
        raise ConfigError(f"{where}: frame(s) {brief(repeated)} given more than once")
    for src in scenes:
        n = src.frames
        bad = [k for k in raw if not 0 <= k < n]
        if bad:
            raise ConfigError(f"{where}: frame(s) {brief(bad)} outside 0..{n - 1} of scene {src.source}")
    return tuple(raw)
