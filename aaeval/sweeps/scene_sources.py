"""The scenes of a config's group: scene files, generators' difficulty ladders, and
``animate`` tables that set a group's scenes moving.

Each scene is a :class:`SceneSource`: its document (what the scene is made of), the name it
has in tables, and its difficulty; it is parsed (and so checked) once, where the config is
read. A scene listed twice in a group is refused: every cell is one row of the results.
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, Mapping

from aaeval._toml import read_toml
from aaeval.scenes import Scene, SceneError, parse_scene
from aaeval.scenes.generate import GENERATORS, generate_scene
from aaeval.sweeps.config_keys import ConfigError, brief, refuse_unknown

__all__ = ["SceneSource", "read_scenes", "animated", "MAX_LADDER", "LEVEL_SECONDS"]

#: The most steps of one generator's difficulty ladder; LEVEL_SECONDS is about what one
#: step costs at parse time (generate and check its scene), for the estimate in the refusal.
MAX_LADDER = 1000
LEVEL_SECONDS = 0.01


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


def read_scenes(raw: list, where: str, base: Path) -> tuple[SceneSource, ...]:
    """A group's ``scenes`` list (checked a non-empty list by its key), each entry read and
    parsed: scene paths relative to ``base``, the config's folder."""
    out: list[SceneSource] = []
    for i, item in enumerate(raw):
        here = f"{where}[{i}]"
        if isinstance(item, str):
            out.append(_scene_file(item, here, base))
        elif isinstance(item, Mapping) and "generator" in item:
            out.extend(_generated(item, here))
        elif isinstance(item, Mapping) and "path" in item:
            refuse_unknown(item, {"path", "difficulty", "difficulty_label"}, here)
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
        raise ConfigError(f"{where}.difficulty: expected a non-empty list of difficulty values, got {brief(levels)}")
    params = {k: v for k, v in item.items() if k not in ("generator", "difficulty")}
    out = []
    try:
        counts = Counter(levels)
    except TypeError:  # an unhashable value (a table): refused as not a number below
        counts = Counter()
    repeated = sorted((d for d, n in counts.items() if n > 1), key=str)
    if repeated:
        raise ConfigError(f"{where}.difficulty: value(s) {brief(repeated)} given more than once")
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


def animated(scenes: tuple[SceneSource, ...], raw: Mapping, where: str) -> tuple[SceneSource, ...]:
    """Give every scene of the group this [animation] table (static scenes set moving)."""
    refuse_unknown(raw, {"frames", "translate", "phases", "seed"}, where)
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
