"""The summary kinds a ``study.toml`` may name (:data:`SUMMARIES`): each one's title, keys,
expectations, check before the sweep and writer after it, and the check every table passes."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from aaeval._toml import refuse_unknown_keys
from aaeval.studies.checks import (check_errors, check_figure, check_hidden_lines, check_pairs, check_pixel,
                                   check_temporal, config_method)
from aaeval.studies.drawn_summaries import write_figure, write_hidden_lines
from aaeval.studies.fields import name_list, number_field
from aaeval.studies.folder import MAX_TEXT, StudyError, brief
from aaeval.studies.frame_summaries import write_sums, write_temporal
from aaeval.studies.image_summaries import write_errors, write_pairs, write_pixel


def _no_check(item: Mapping, group, where: str, folder: Path) -> None:
    return None


@dataclass(frozen=True)
class Summary:
    """One summary kind: its default title, keys, expectations, writer and check."""

    title: str
    keys: set[str]  # its keys in study.toml besides kind, title and note
    write: Callable[..., list[str]]  # write(sweep, item, study, where, checks) -> markdown lines
    expects: set[str] = field(default_factory=set)  # its expectation keys (see verdict)
    check: Callable[..., None] = _no_check  # check(item, group, where, folder): before the sweep


#: Summary kinds a study.toml may name: title, keys, writer.
SUMMARIES: dict[str, Summary] = {
    "sums": Summary("Intensity sum per frame", {"group", "tolerance"}, write_sums, {"steady", "unsteady"}),
    "temporal": Summary("Over the animation", {"group", "metrics", "ratio"}, write_temporal, {"ratio_above", "ratio_below"},
                        check_temporal),
    "errors": Summary("Error against the reference", {"group", "metrics", "noise_factor"}, write_errors, {"within_noise"},
                      check_errors),
    "pairs": Summary("Difference between two methods", {"group", "pairs"}, write_pairs, {"below"}, check_pairs),
    "pixel": Summary("One pixel", {"group", "pixel", "frame", "tolerance"}, write_pixel, {"agree", "disagree"},
                     check_pixel),
    "hidden_lines": Summary("Hidden lines", {"scenes"}, write_hidden_lines, check=check_hidden_lines),
    "figure": Summary("Figure", {"figure"}, write_figure, check=check_figure),
}

#: Keys holding a number >= 0 and keys holding a list of the group's methods, whatever the kind.
_NUMBERS = {"tolerance", "noise_factor", "below", "ratio_above", "ratio_below"}
_NAME_LISTS = {"steady", "unsteady", "agree", "disagree", "within_noise"}


def check_summary(item: Any, where: str, groups: Mapping[str, Any], folder: Path) -> None:
    """Every field of one ``[[summaries]]`` table: its type, and the groups, methods, metrics,
    frames and pixels it names against the experiment config, so nothing is refused after the sweep."""
    if not isinstance(item, Mapping):
        raise StudyError(f"{where}: expected a table, got {brief(item)}")
    kind = item.get("kind")
    if not isinstance(kind, str) or kind not in SUMMARIES:
        raise StudyError(f"{where}.kind: {brief(kind)} is not a summary kind; kinds: {', '.join(sorted(SUMMARIES))}")
    summary = SUMMARIES[kind]
    refuse_unknown_keys(item, summary.keys | summary.expects | {"kind", "title", "note"}, where, StudyError)
    for key in ("title", "note"):
        if key in item and (not isinstance(item[key], str) or len(item[key]) > MAX_TEXT):
            raise StudyError(f"{where}.{key}: expected a string of at most {MAX_TEXT} characters, got {brief(item[key])}")
    for key in _NUMBERS & set(item):
        number_field(item, key, 0, where)
    group = None
    if "group" in summary.keys:
        name = item.get("group")
        if not isinstance(name, str) or name not in groups:
            raise StudyError(f"{where}.group: {brief(name)} is not a group of the config (groups: {sorted(groups)})")
        group = groups[name]
    for key in sorted(_NAME_LISTS & set(item)):
        for name in name_list(item, key, where):
            config_method(group, name, f"{where}.{key}")
    summary.check(item, group, where, folder)
