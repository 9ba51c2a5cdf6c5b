"""Each summary kind's check of its ``[[summaries]]`` table against the experiment config, run
when the study is loaded so that nothing is refused after the sweep has run."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from aaeval.studies.fields import canonical_spec, name_list
from aaeval.studies.folder import MAX_ITEMS, StudyError, brief


def config_method(group, name: str, where: str) -> None:
    """``name`` is one of ``group``'s methods: a spec as the config writes it, or its label."""
    canonical = canonical_spec(name)
    options = {k for spec in group.specs for k in spec.options}
    varying = {k for k in options if len({repr(s.options.get(k)) for s in group.specs}) > 1}
    known = {str(s) for s in group.specs} | {s.label() for s in group.specs} | {s.label(varying) for s in group.specs}
    if name not in known and canonical not in known:
        raise StudyError(f"{where}: {brief(name)} is not a method of the group {group.name!r} "
                         f"(specs: {[str(s) for s in group.specs]})")


def _method_pair(group, value: Any, where: str) -> None:
    if not (isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) for v in value)):
        raise StudyError(f"{where}: expected two of the group's methods, [method, method], got {brief(value)}")
    for name in value:
        config_method(group, name, where)


def _check_metrics(group, item: Mapping, where: str, measured: tuple[str, ...], default: list[str] | None) -> None:
    for name in name_list(item, "metrics", where, default):
        if name not in measured:
            raise StudyError(f"{where}.metrics: {brief(name)} is not measured by the group {group.name!r} "
                             f"(it measures {list(measured)})")


def check_temporal(item: Mapping, group, where: str, folder: Path) -> None:
    if not group.temporal:
        raise StudyError(f"{where}.group: {group.name!r} measures no temporal metric (its scenes do not move)")
    _check_metrics(group, item, where, group.temporal, None)
    if "ratio" in item:
        _method_pair(group, item["ratio"], f"{where}.ratio")
    elif {"ratio_above", "ratio_below"} & set(item):
        raise StudyError(f"{where}: ratio_above / ratio_below bound a ratio: give ratio = [method, method]")


def check_errors(item: Mapping, group, where: str, folder: Path) -> None:
    from aaeval.sweeps.measure import reference_kind

    _check_metrics(group, item, where, group.metrics, ["rmse"])
    if "within_noise" in item and reference_kind(group.reference) == "deterministic":
        raise StudyError(f"{where}.within_noise: the group's reference {str(group.reference)!r} is neither seeded nor "
                         "exact: its own error is unknown, so nothing can be within it")


def check_pairs(item: Mapping, group, where: str, folder: Path) -> None:
    pairs = item.get("pairs")
    if not isinstance(pairs, list) or not pairs or len(pairs) > MAX_ITEMS:
        raise StudyError(f"{where}.pairs: expected a list of 1 to {MAX_ITEMS} [method, method] pairs, "
                         f"got {brief(pairs)}")
    for pair in pairs:
        _method_pair(group, pair, f"{where}.pairs")


def _integer(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def check_pixel(item: Mapping, group, where: str, folder: Path) -> None:
    pixel = item.get("pixel")
    if not (isinstance(pixel, list) and len(pixel) == 2 and all(_integer(v) and v >= 0 for v in pixel)):
        raise StudyError(f"{where}.pixel: expected [row, column], two integers >= 0, got {brief(pixel)}")
    frame = item.get("frame", 0)
    if not _integer(frame) or frame < 0:
        raise StudyError(f"{where}.frame: expected a frame number >= 0, got {brief(frame)}")
    for source in group.scenes:
        scene = source.parsed
        frames = range(scene.frames) if group.frames == "all" else group.frames
        if frame not in frames:
            raise StudyError(f"{where}.frame: frame {frame} is not among the frames the group renders of {source.name}")
        if not (pixel[0] < scene.height and pixel[1] < scene.width):
            raise StudyError(f"{where}.pixel: {pixel} is outside the {scene.height}x{scene.width} image of {source.name}")


def check_hidden_lines(item: Mapping, group, where: str, folder: Path) -> None:
    from aaeval.scenes import SceneError, load_scene

    scenes = item.get("scenes")
    if (not isinstance(scenes, list) or not scenes or len(scenes) > MAX_ITEMS
            or not all(isinstance(s, str) and s for s in scenes)):
        raise StudyError(f"{where}.scenes: expected a list of 1 to {MAX_ITEMS} scene files (relative to the study "
                         f"folder), got {brief(scenes)}")
    stems = [Path(s).stem for s in scenes]
    if len(set(stems)) != len(stems):
        raise StudyError(f"{where}.scenes: two scenes share a file name; each drawing is named after its scene")
    for rel in scenes:
        try:
            load_scene(folder / rel)
        except (SceneError, ValueError) as exc:
            raise StudyError(f"{where}.scenes: {exc}") from None


def check_figure(item: Mapping, group, where: str, folder: Path) -> None:
    from aaeval.studies.figures import FIGURES

    name = item.get("figure")
    if not isinstance(name, str) or name not in FIGURES:
        raise StudyError(f"{where}.figure: {brief(name)} is not a study figure; figures: {', '.join(sorted(FIGURES))}")
