"""A summary's fields: the numbers and name lists of one ``[[summaries]]`` table, checked as they
are read, and the rows of the results they pick (a group, a method named by label or spec)."""

from __future__ import annotations

import math
from typing import Mapping

from aaeval.studies.folder import MAX_ITEMS, StudyError, brief


def number_field(item: Mapping, key: str, default: float, where: str) -> float:
    value = item.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise StudyError(f"{where}.{key}: expected a finite number >= 0, got {brief(value)}")
    return float(value)


def name_list(item: Mapping, key: str, where: str, default: list[str] | None = None) -> list[str]:
    value = item.get(key, default)
    if (not isinstance(value, list) or not value or len(value) > MAX_ITEMS
            or not all(isinstance(m, str) for m in value)):
        raise StudyError(f"{where}.{key}: expected a list of 1 to {MAX_ITEMS} names, got {brief(value)}")
    return value


def group_rows(frame, item: Mapping, where: str):
    group = item.get("group")
    if not isinstance(group, str):
        raise StudyError(f"{where}.group: expected the name of one of the config's groups")
    rows = frame[frame["group"] == group]
    if rows.empty:
        known = sorted(set(frame["group"])) if "group" in frame else []
        raise StudyError(f"{where}.group: {group!r} has no rows in the results (groups: {known})")
    return rows


def labels_in(rows) -> list[str]:
    return list(dict.fromkeys(rows["label"]))  # the config's order


def method_rows(rows, name: str, where: str):
    """The rows of the method ``name``: its label in the tables or its spec as the sweep wrote
    it (``weiler-atherton:window=8``), so a study names methods as its config does."""
    canonical = canonical_spec(name)
    picked = rows[(rows["label"] == name) | (rows["spec"].astype(str).isin({name, canonical}))]
    if picked.empty:
        raise StudyError(f"{where}: {name!r} is not a method of the group (labels: {labels_in(rows)}; "
                         f"specs: {list(dict.fromkeys(rows['spec'].astype(str)))})")
    return picked


def expected_labels(item: Mapping, key: str, rows, where: str) -> list[str]:
    """The labels of the methods an expectation ``key`` names (none when the key is absent)."""
    if key not in item:
        return []
    return [method_rows(rows, name, f"{where}.{key}")["label"].iloc[0] for name in name_list(item, key, where)]


def canonical_spec(name: str) -> str:
    """A method as the sweep writes its spec ("convex=false" is written "convex=False"); the name
    itself where it does not parse."""
    from aaeval.renderers import MethodError, MethodSpec

    try:
        return str(MethodSpec.parse(name))
    except MethodError:
        return name
