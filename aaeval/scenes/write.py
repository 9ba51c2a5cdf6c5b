"""The scene writer, beside the reader (:mod:`aaeval.scenes.format`): a scene or a scene
document back to TOML.

- :func:`write_scene` writes a :class:`~aaeval.scenes.format.Scene` in the core keys only;
  reading the file again gives the same numbers bit for bit (floats are written with
  ``repr``).
- :func:`write_scene_document` writes a scene dictionary as given (core keys, polygons
  with holes, extension tables such as ``[text]``), after validating it: the importers'
  writer.

Both write atomically (:func:`aaeval.imageio.atomic_write`) and put ``comment`` as a
``#`` header.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

from aaeval.imageio import atomic_write
from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import Scene, SceneError

__all__ = ["scene_to_dict", "write_scene", "write_scene_document", "comment_header", "toml_value"]


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The core-key dictionary of a scene at frame 0 (what its TOML file parses to).

    A scene at a later frame is first moved back to frame 0, which may change the last
    bit of its coordinates (``x + k t - k t``); a scene at frame 0 is written exactly.

    Raises
    ------
    ValueError
        The scene carries extension tables, which the core format cannot hold.
    """
    if scene.extensions:
        raise ValueError(
            f"{scene.source}: scene has extension tables {sorted(scene.extensions)}; "
            "only the core keys can be written"
        )
    scene = scene.at_frame(0)
    document: dict[str, Any] = {
        "image": {
            "width": scene.width,
            "height": scene.height,
            "background": scene.background.tolist(),
        }
    }
    if scene.frames != 1 or scene.translate.any():
        document["animation"] = {"frames": scene.frames, "translate": scene.translate.tolist()}
        if scene.phases != "none":  # written only when set: a file without it reads as before
            document["animation"]["phases"] = scene.phases
            if scene.phases == "random":
                document["animation"]["seed"] = scene.phase_seed
    document["polygons"] = [
        {"color": p.color.tolist(), "vertices": p.vertices.tolist()} for p in scene.polygons
    ]
    return document


def write_scene(scene: Scene | Mapping[str, Any], path: str | Path, *, comment: str | None = None) -> Path:
    """Write a scene (or a scene dictionary) as TOML in the core keys, atomically.

    A dictionary is validated with :func:`parse_scene` first, so nothing invalid is
    written. ``comment`` becomes a ``#`` header. Returns the path.
    """
    path = Path(path)
    if not isinstance(scene, Scene):
        scene = parse_scene(scene, source=str(path))
    return _write(scene_to_dict(scene), path, comment)


def write_scene_document(document: Mapping[str, Any], path: str | Path, *, comment: str | None = None) -> Path:
    """Validate and write a scene dictionary (core keys, holes, extension tables) as TOML, atomically."""
    path = Path(path)
    parse_scene(document, source=str(path))  # nothing invalid is written
    return _write(document, path, comment)


def _write(document: Mapping[str, Any], path: Path, comment: str | None) -> Path:
    lines: list[str] = []
    for key, table in document.items():
        if key == "polygons":
            continue
        lines += ["", f"[{key}]"] + [f"{k} = {toml_value(v)}" for k, v in table.items()]
    for p in document["polygons"]:
        lines += ["", "[[polygons]]", f"color = {toml_value(p['color'])}", "vertices = ["]
        lines += [f"  {toml_value(v)}," for v in p["vertices"]]
        lines.append("]")
        if "holes" in p:
            lines.append("holes = [")
            for hole in p["holes"]:
                lines += ["  ["] + [f"    {toml_value(v)}," for v in hole] + ["  ],"]
            lines.append("]")
    text = comment_header(comment) + "\n".join(lines).lstrip("\n") + "\n"
    atomic_write(path, lambda tmp: Path(tmp).write_text(text))
    return path


def comment_header(comment: str | None) -> str:
    """``comment`` as ``#`` lines and a blank line (nothing for no comment)."""
    if not comment:
        return ""
    return "".join(f"# {line}".rstrip() + "\n" for line in comment.strip("\n").splitlines()) + "\n"


def toml_value(v: Any) -> str:
    """A TOML value: a number (floats by ``repr``, read back bit for bit), a string, or a list."""
    if isinstance(v, bool):
        raise SceneError(f"booleans have no place in the scene format, got {v!r}")
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise SceneError(f"non-finite number {v!r} cannot be written")
        return repr(v)  # shortest string that reads back as the same float; valid TOML
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} in a scene file")
