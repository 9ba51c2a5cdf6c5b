"""Summaries that draw into the study folder: Weiler-Atherton's hidden-line drawings
(``hidden-lines/``) and the paper's figures made again (``figures/``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Mapping
from urllib.parse import quote

from aaeval.studies.folder import Study, StudyError, refuse_link
from aaeval.studies.markdown import fmt, md_code, md_table

def write_hidden_lines(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """Weiler-Atherton's visible edges of each named scene, drawn into ``hidden-lines/`` of the
    study folder: segments kept and their length against every polygon outline's length."""
    from aaeval.imageio import atomic_write
    from aaeval.scenes import SceneError, load_scene
    from aaeval.weiler_atherton.lines import hidden_line_svg, visible_edges

    folder = study.output / "hidden-lines"
    table = []
    for rel in item["scenes"]:  # checked by check_hidden_lines
        try:
            scene = load_scene(study.folder / rel)
        except SceneError as exc:
            raise StudyError(f"{where}.scenes: {exc}") from None
        edges = visible_edges(scene)
        visible = sum(math.dist(p, q) for p, q, _ in edges)
        outline = sum(math.dist(poly.vertices[k][:2], poly.vertices[(k + 1) % len(poly.vertices)][:2])
                      for poly in scene.polygons for k in range(len(poly.vertices)))
        svg = hidden_line_svg(scene)
        target = folder / f"{Path(rel).stem}.svg"
        refuse_link(folder)  # at the write: the folder may have become a link since the study was loaded
        atomic_write(target, lambda tmp, svg=svg: Path(tmp).write_text(svg))
        table.append([f"[{md_code(Path(rel).stem)}](hidden-lines/{quote(target.name)})", str(len(scene.polygons)), str(len(edges)),
                      fmt(visible, ".2f"), fmt(outline, ".2f")])
    return md_table(["scene (drawing)", "polygons", "visible segments", "visible length (px)",
                   "all outlines (px)"], table) + [""]


def write_figure(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """One of the paper's figures made again (:data:`aaeval.studies.figures.FIGURES`), drawn into
    ``figures/`` of the study folder."""
    from aaeval.studies.figures import FIGURES

    folder = study.output / "figures"
    refuse_link(folder)  # at the write: the folder may have become a link since the study was loaded
    folder.mkdir(parents=True, exist_ok=True)
    return FIGURES[item["figure"]].draw(folder) + [""]
