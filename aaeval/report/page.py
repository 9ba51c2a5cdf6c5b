"""What one report build shares (:class:`Page`): the sweep's data, the folders the figures,
tables and viewer data go to, the styles, the failure definition and the viewer's byte budget;
and how a figure and the definition sit on the page."""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.report import figures
from aaeval.report.html_tables import Stored, shown, stored_cells, write_table
from aaeval.report.style import Styles
from aaeval.report.sweep_data import SweepData
from aaeval.sweeps.aggregate import failure_definition
from aaeval.sweeps.summaries import measured_noise


# The page must stay small (figures' PNG, SVG and PDF, tables and this, under 20 MB): past
# this many bytes of viewer data, a group's viewer keeps its first scene only.
VIEWER_BUDGET = 4_000_000


def definition_html(definition: str, fail_above, stored_at: Stored) -> str:
    """The failure definition with its threshold marked as the value stored in the manifest."""
    text = html.escape(definition)
    if not fail_above:
        return text
    number = f"{fail_above:g}"
    i = text.rindex(f"above {number}") + len("above ")
    return text[:i] + shown(fail_above, stored_at, number) + text[i + len(number):]


def figure_html(path: Path, root: Path, caption: str) -> str:
    """A figure of the page: the PNG, its caption, and links to its twins in other formats."""
    rel = path.relative_to(root).as_posix()
    twins = " · ".join(f"<a href='{html.escape(Path(rel).with_suffix('.' + f).as_posix())}'>{f.upper()}</a>"
                       for f in figures.twin_formats())
    links = f" <span class='dl'>(also as {twins})</span>" if twins else ""
    return (f"<figure><img src='{html.escape(rel)}' alt='{html.escape(html.unescape(''.join(p.split('>', 1)[-1] for p in caption.split('<')))[:120])}'>"
            f"<figcaption>{caption}{links}</figcaption></figure>")


class Page:
    """What one report build shares: folders, styles, the failure definition."""

    def __init__(self, data: SweepData):
        store, results, manifest = data.store, data.results, data.manifest
        self.store, self.root, self.data = store, store.root, data
        # real folders of the sweep folder (a planted link to a folder elsewhere is refused by name)
        self.figdir, self.tabdir, self.viewdir = (store.own_folder(d) for d in ("figures", "tables", "viewer"))
        self.primary = manifest.get("primary", "rmse")
        self.fail_above = manifest.get("fail_above")
        self.styles = Styles.from_sweep(data.specs)
        self.definition = failure_definition(self.primary, self.fail_above)
        # the definition as running text, its threshold marked as the manifest's value
        self.definition_html = definition_html(self.definition, self.fail_above,
                                               Stored("manifest.json", 0, "fail_above"))
        self.viewer_scripts: list[str] = []
        self.viewer_left = VIEWER_BUDGET  # bytes of viewer data the page may still load
        self.shaded = set(results.loc[results["shaded"].astype(bool), "scene_digest"]) if not results.empty else set()
        self.group_temporal = manifest.get("group_temporal", {})

    def table(self, frame: pd.DataFrame, name: str, caption: str = "", where: pd.DataFrame | None = None) -> str:
        # names: fixed words and figure stems
        return write_table(frame, self.tabdir, name, self.root, caption, where)

    def stored_table(self, frame: pd.DataFrame, source: str, name: str, caption: str = "",
                     renamed: dict | None = None) -> str:
        """Rows of the stored table ``source`` (``frame``'s index: their stored rows), its
        columns ``renamed`` (``{stored name: shown name}``) for the page."""
        shown_frame = frame.rename(columns=renamed or {})
        return self.table(shown_frame.reset_index(drop=True), name, caption,
                          stored_cells(shown_frame, source, frame.index, renamed).reset_index(drop=True))

    def references(self, group: str) -> pd.DataFrame:
        refs = self.data.summary("references")
        return refs[refs["group"] == group] if not refs.empty else refs


def truth_noise(rows: pd.DataFrame) -> np.ndarray:
    """The ground truth's measured noise of each scene frame of ``rows``: the grey band of a
    chart (none for a noise-free truth)."""
    return measured_noise(rows.drop_duplicates(["scene", "frame"])).to_numpy(float)
