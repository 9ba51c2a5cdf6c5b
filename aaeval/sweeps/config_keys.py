"""The keys of an experiment config, each declared once as an :class:`~aaeval.options.Option`.

Three tables: :data:`EXPERIMENT_KEYS` (``[experiment]``), :data:`GROUP_KEYS` (each
``[[groups]]`` table) and :data:`SPEED_KEYS` (each ``[[speed]]`` table). Each entry names a
key, says what it means, gives its default (:data:`REQUIRED`: the key must be given; None: the
default is computed from other keys, as its doc says) and the values it takes. A key's raw TOML
value becomes a checked value in one place, :func:`read_key`, through
:meth:`Option.convert <aaeval.options.Option.convert>`; a key outside its table is refused.
What one key cannot check alone (a metric name against the registry, a spec against the
methods, frames against the scenes) is checked where the config is put together.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

from aaeval._toml import refuse_unknown_keys
from aaeval.catmull import MAX_THREADS
from aaeval.metrics import MetricError, check_metric_names
from aaeval.options import Option
from aaeval.renderers import MethodError, MethodSpec

__all__ = ["ConfigError", "REQUIRED", "EXPERIMENT_KEYS", "GROUP_KEYS", "SPEED_KEYS", "MAX_REPEATS",
           "MAX_CELL_SECONDS", "read_key", "refuse_unknown", "metric_names", "method_spec", "brief"]


class ConfigError(ValueError):
    """An experiment config breaks a rule; the message names the file and the key."""


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


#: The default of a key that must be given.
REQUIRED = _Required()

#: More timed renders per cell than any timing needs: a typo such as 1e9 would run for days.
MAX_REPEATS = 1000

#: The largest per-cell time limit a config may set (a day): above it, no limit at all.
MAX_CELL_SECONDS = 86400.0


def _filled(text: str) -> str | None:
    return None if text.strip() else "empty"


def _listed(kind: str):
    """A check that a list is non-empty and holds strings only (``kind`` names them)."""
    def check(values: list) -> str | None:
        return None if values and all(isinstance(v, str) for v in values) else f"not a non-empty list of {kind}"
    return check


def _names(values: list) -> str | None:
    return None if all(isinstance(v, str) for v in values) else "not a list of names"


_TEXT = "a non-empty string"
_REPEATS = Option(int, 1, "timed renders per cell, after one untimed warm-up", minimum=1, maximum=MAX_REPEATS,
                  words=f"a whole number of timed renders from 1 to {MAX_REPEATS}")
_METRICS = Option(list, None, "per-frame metrics (names: `aaeval metrics`); left out: every registered metric "
                  "that applies to a group's scenes", check=_listed("metric names"),
                  words="a non-empty list of metric names")
_TEMPORAL = Option(list, None, "metrics over the frames of an animation; left out: every applicable one, for "
                   "groups whose scenes move", check=_names, words="a list of metric names")
_SCENES = Option(list, REQUIRED, "scene files (relative to the config), {path = ..., difficulty = ...} tables "
                 "and {generator = ..., difficulty = [...]} ladders", check=lambda v: None if v else "empty",
                 words="a non-empty list of scene files or generator tables")
_METHODS = Option(list, REQUIRED, "method specs (`supersample:k=4`)", check=_listed("method specs"),
                  words="a non-empty list of method specs")
_OPTIONS = Option(dict, {}, "option = [values], expanded for every method that declares the option; "
                  "options.METHOD = {...} for one method only", words="a table of option = [values]")

EXPERIMENT_KEYS: dict[str, Option] = {
    "name": Option(str, None, "the experiment's name; left out: the config file's stem", check=_filled, words=_TEXT),
    "description": Option(str, "", "what the experiment measures, for the report"),
    "reference": Option(str, REQUIRED, "method spec every cell is compared against", check=_filled, words=_TEXT),
    "metrics": _METRICS,
    "temporal": _TEMPORAL,
    "primary": Option(str, None, "the error axis of the report's charts; left out: the first of metrics, else rmse",
                      check=_filled, words=_TEXT),
    "noise_estimate": Option(bool, True, "seeded references: measure their noise with a second seed",
                             words="true or false"),
    # a nan would never compare above: finite is part of the rule
    "fail_above": Option(float, None, "a cell whose primary error exceeds this counts as failed; left out: none",
                         minimum=0.0, low_open=True, words="a finite positive number"),
    "repeats": _REPEATS,
    "max_seconds": Option(float, None, "time limit of one cell or reference, all its repeats; left out: "
                          "AAEVAL_MAX_SECONDS, else 600", minimum=0.0, maximum=MAX_CELL_SECONDS, low_open=True,
                          words=f"a number of seconds above 0 and at most {MAX_CELL_SECONDS:g} (a day)"),
}

GROUP_KEYS: dict[str, Option] = {
    "name": Option(str, REQUIRED, "the group's name, unique in the experiment", check=_filled, words=_TEXT),
    "scenes": _SCENES,
    "methods": _METHODS,
    "frames": Option(object, "all", "\"all\" (every frame of each scene) or a list of frame numbers"),
    "options": _OPTIONS,
    "reference": replace(EXPERIMENT_KEYS["reference"], default=None, doc="overrides [experiment].reference"),
    "metrics": replace(_METRICS, doc="overrides [experiment].metrics"),
    "temporal": replace(_TEMPORAL, doc="overrides [experiment].temporal"),
    "animate": Option(dict, None, "an [animation] table every scene of the group is given (static scenes set "
                      "moving)", words="a table {frames = N, translate = [dx, dy], phases = \"r2\"}"),
    "repeats": replace(_REPEATS, default=None, doc="overrides [experiment].repeats"),
}

SPEED_KEYS: dict[str, Option] = {
    "scenes": replace(_SCENES, doc=f"{_SCENES.doc}, each of 256 x 256 pixels or more"),
    "methods": _METHODS,
    "options": _OPTIONS,
    "repeats": replace(_REPEATS, default=5, doc="interleaved rounds after a warm-up of each spec"),
    "threads": Option(int, 1, "given to every method that has a threads option and whose spec sets none",
                      minimum=1, maximum=MAX_THREADS, words=f"a whole number of threads from 1 to {MAX_THREADS}"),
    "accuracy": Option(str, None, "the group whose errors the speed-accuracy chart pairs with these times",
                       words="the name of a group of this experiment"),
}


def read_key(table: Mapping, keys: Mapping[str, Option], key: str, where: str) -> Any:
    """``table[key]`` checked by its declared option (``where.key`` in a refusal), or the
    key's default when the table leaves it out; a :data:`REQUIRED` key left out is refused."""
    option = keys[key]
    if key not in table:
        if option.default is REQUIRED:
            raise ConfigError(f"{where}: missing required key '{key}'")
        return option.default
    return option.convert(table[key], f"{where}.{key}", ConfigError, text=False)


def refuse_unknown(table: Mapping, keys: Mapping[str, Any], where: str) -> None:
    """Refuse every key of ``table`` that ``keys`` does not declare, naming them."""
    refuse_unknown_keys(table, set(keys), where, ConfigError)


def metric_names(names: list, where: str, *, temporal: bool) -> tuple[str, ...]:
    """A checked ``metrics`` or ``temporal`` list, each name a registered metric of its kind."""
    try:
        return check_metric_names(names, "temporal" if temporal else "image")
    except MetricError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def method_spec(text: str, where: str) -> MethodSpec:
    """A ``reference`` key's spec, parsed."""
    try:
        return MethodSpec.parse(text)
    except MethodError as exc:
        raise ConfigError(f"{where}: {exc}") from None


def brief(values: Any, limit: int = 10) -> str:
    """A list shown by its first ``limit`` items and its length: an error line must stay
    readable when a config holds a million values."""
    if isinstance(values, (list, tuple)) and len(values) > limit:
        return f"[{', '.join(repr(v)[:40] for v in values[:limit])}, ... ({len(values)} in all)]"
    text = repr(values)
    return text if len(text) <= 200 else text[:200] + "..."
