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

Every key is declared once, with its meaning and default, in :mod:`aaeval.sweeps.config_keys`,
and checked before any work starts; an error names the file and the key. A group expands into
cells in :mod:`aaeval.sweeps.cells`, its scenes are read in :mod:`aaeval.sweeps.scene_sources`,
and what a config may ask for is budgeted in :mod:`aaeval.sweeps.config_budgets`. A
config that repeats itself (a scene, a difficulty or a method spec given twice in a group)
is refused, naming the key: every cell of a config is one row of the results table.
Scene paths are relative to the config file.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from aaeval._toml import read_toml
from aaeval.renderers import MethodSpec
from aaeval.sweeps.cells import Cell, Group, expand_specs, read_group
from aaeval.sweeps.config_budgets import check_cell_count, check_speed_budget
from aaeval.sweeps.config_keys import (EXPERIMENT_KEYS, SPEED_KEYS, ConfigError, metric_names, method_spec, read_key,
                                       refuse_unknown)
from aaeval.sweeps.scene_sources import SceneSource, read_scenes

__all__ = ["Experiment", "SpeedPass", "load_experiment", "parse_experiment", "SPEED_MIN_PIXELS"]

#: The speed pass times images of at least this many pixels (below, a render is call overhead).
SPEED_MIN_PIXELS = 256 * 256


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
    """A config, read: its groups, the speed pass, and what judges a cell."""

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
    at = f"{where}: [experiment]"
    refuse_unknown(head, EXPERIMENT_KEYS, at)
    given = {key: read_key(head, EXPERIMENT_KEYS, key, at) for key in EXPERIMENT_KEYS}
    name = given["name"] or Path(where).stem
    reference = method_spec(given["reference"], f"{at}.reference")
    # None: a group names none and measures every registered metric that applies to its scenes
    metrics = None if given["metrics"] is None else metric_names(given["metrics"], f"{at}.metrics", temporal=False)
    temporal = None if given["temporal"] is None else metric_names(given["temporal"], f"{at}.temporal", temporal=True)
    primary = given["primary"] or (metrics[0] if metrics else "rmse")
    max_seconds = given["max_seconds"]

    raw_groups = document.get("groups")
    if not isinstance(raw_groups, list) or not raw_groups:
        raise ConfigError(f"{where}: needs at least one [[groups]] table")
    groups = [read_group(raw, f"{where}: groups[{i}]", base, reference, metrics, given["repeats"], temporal)
              for i, raw in enumerate(raw_groups)]
    temporal = tuple(dict.fromkeys(m for g in groups for m in g.temporal))
    check_cell_count(groups, where)
    for i, g in enumerate(groups):  # a cell no run would finish is refused now, not stopped at its limit
        check_speed_budget(g.scenes, g.specs, g.repeats, f"{where}: groups[{i}]", max_seconds, what="cell")
    names = [g.name for g in groups]
    dup = sorted(n for n, k in Counter(names).items() if k > 1)
    if dup:
        raise ConfigError(f"{where}: groups.name must be unique, repeated: {dup}")
    if not any(primary in g.metrics for g in groups):
        raise ConfigError(f"{at}.primary {primary!r} is not a metric of any group")
    raw_speed = document.get("speed", [])
    if not isinstance(raw_speed, list):
        raise ConfigError(f"{where}: speed must be an array of [[speed]] tables")
    speed = tuple(_speed(raw, f"{where}: speed[{i}]", base, set(names), max_seconds)
                  for i, raw in enumerate(raw_speed))
    return Experiment(name, given["description"], where, text, tuple(groups), temporal, primary,
                      given["noise_estimate"], given["fail_above"], speed, max_seconds)


def _speed(raw: Any, where: str, base: Path, groups: set[str], limit: float | None = None) -> SpeedPass:
    """One ``[[speed]]`` table (:data:`~aaeval.sweeps.config_keys.SPEED_KEYS`): its specs,
    with ``threads`` given to every method that has the option and whose spec sets none."""
    if not isinstance(raw, Mapping):
        raise ConfigError(f"{where}: must be a table")
    refuse_unknown(raw, SPEED_KEYS, where)
    given = {key: read_key(raw, SPEED_KEYS, key, where) for key in SPEED_KEYS}
    scenes = read_scenes(given["scenes"], f"{where}.scenes", base)
    for src in scenes:
        if src.parsed.width * src.parsed.height < SPEED_MIN_PIXELS:
            raise ConfigError(f"{where}.scenes: {src.name} is {src.parsed.width}x{src.parsed.height}; the speed pass "
                              f"times images of at least {SPEED_MIN_PIXELS} pixels (256 x 256)")
    repeats, threads = given["repeats"], given["threads"]
    specs = []
    for spec, named in expand_specs(given["methods"], given["options"], where, with_given=True):
        if "threads" in spec.method.options and "threads" not in named:
            spec = spec.with_options(threads=threads)
        specs.append(spec)
    check_speed_budget(scenes, specs, repeats, where, limit)
    accuracy = given["accuracy"]
    if accuracy is not None and accuracy not in groups:
        raise ConfigError(f"{where}.accuracy: {accuracy!r} is not a group of this experiment ({sorted(groups)})")
    return SpeedPass(scenes, tuple(specs), repeats, threads, accuracy)
