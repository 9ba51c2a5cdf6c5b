"""The report's tables: each shown as HTML and written beside the page as CSV and LaTeX
(``DIR/tables/<name>.csv``, ``.tex``), ready for a paper.

Every value the page shows is one cell of a table the sweep stored: an HTML cell or span
names it with ``data-source`` (the file, relative to the sweep folder), ``data-row`` (its
row, from 0), ``data-column`` and, where the page formats it otherwise than :func:`fmt`,
``data-fmt`` (a format spec for :func:`aaeval.metrics.info.format_value`). The tests look
each one up (:class:`Stored`)."""

from __future__ import annotations

import html
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.fileio import atomic_write
from aaeval.metrics.info import format_value

__all__ = ["html_table", "write_table", "latex_table", "fmt", "Stored", "stored_cells", "shown"]


@dataclass(frozen=True)
class Stored:
    """Where a value of the page is stored: ``source`` (a file of the sweep folder), the
    row and column there, and the format the page shows it in ("" for :func:`fmt`)."""

    source: str
    row: int
    column: str
    fmt: str = ""

    def attributes(self) -> str:
        attrs = (f"data-source='{html.escape(self.source)}' data-row='{int(self.row)}' "
                 f"data-column='{html.escape(str(self.column))}'")
        return attrs + (f" data-fmt='{html.escape(self.fmt)}'" if self.fmt else "")


def shown(value, where: Stored, text: str | None = None) -> str:
    """``value`` as the page shows it in running text, in a span naming where it is stored
    (``text``: the words shown, when they are not the value formatted by ``where.fmt``)."""
    if text is None:
        text = format_value(value, where.fmt) if where.fmt else fmt(value)
    return f"<span class='num' {where.attributes()}>{html.escape(text)}</span>"


def stored_cells(frame: pd.DataFrame, source: str, rows, renamed: dict | None = None) -> pd.DataFrame:
    """Where each cell of ``frame`` is stored: in ``source`` at ``rows`` (one stored row per
    row of ``frame``), in the column of the same name or the one ``renamed`` maps it from
    (``{stored name: shown name}``, as given to :meth:`pandas.DataFrame.rename`)."""
    back = {new: old for old, new in (renamed or {}).items()}
    rows = list(rows)
    return pd.DataFrame({c: [Stored(source, r, back.get(c, c)) for r in rows] for c in frame.columns},
                        index=frame.index)


def fmt(value) -> str:
    """A cell as text: 4 significant digits for floats, nothing for missing values."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, (float, np.floating)):
        return f"{value:.4g}"
    return str(value)


def _numeric(v) -> bool:
    return isinstance(v, (int, float, np.number)) and not isinstance(v, (bool, np.bool_))


def _cell(value, where: Stored | None) -> str:
    attrs = f" {where.attributes()}" if where is not None else ""
    kind = " class='num'" if _numeric(value) else ""
    text = format_value(value, where.fmt) if where is not None and where.fmt else fmt(value)
    return f"<td{kind}{attrs}>{html.escape(text)}</td>"


def html_table(frame: pd.DataFrame, where: pd.DataFrame | None = None) -> str:
    """``frame`` as an HTML table; ``where``: the same shape, each cell's :class:`Stored`
    (or None), written as the cell's ``data-*`` attributes."""
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
    body = []
    for i, row in enumerate(frame.itertuples(index=False)):
        places = where.iloc[i].tolist() if where is not None else [None] * len(row)
        body.append("<tr>" + "".join(_cell(v, w) for v, w in zip(row, places)) + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                  "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def _tex(text: str) -> str:
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in text)


def latex_table(frame: pd.DataFrame, caption: str = "") -> str:
    """A plain ``tabular`` (booktabs rules), numbers right-aligned, text escaped."""
    align = "".join("r" if pd.api.types.is_numeric_dtype(frame[c]) else "l" for c in frame.columns)
    lines = [r"\begin{table}[t]", r"\centering", rf"\begin{{tabular}}{{{align}}}", r"\toprule",
             " & ".join(_tex(str(c)) for c in frame.columns) + r" \\", r"\midrule"]
    for row in frame.itertuples(index=False):
        lines.append(" & ".join(_tex(fmt(v)) for v in row) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}"]
    if caption:
        lines.append(rf"\caption{{{_tex(caption)}}}")
    lines.append(r"\end{table}")
    return "\n".join(lines) + "\n"


def write_table(frame: pd.DataFrame, directory: Path, name: str, root: Path, caption: str = "",
                where: pd.DataFrame | None = None) -> str:
    """Write ``name.csv`` and ``name.tex`` under ``directory``; return the HTML table with
    links to both (relative to the page in ``root``); ``where``: :func:`html_table`'s."""
    directory = Path(directory)
    csv, tex = directory / f"{name}.csv", directory / f"{name}.tex"
    atomic_write(csv, lambda tmp: frame.to_csv(tmp, index=False))
    atomic_write(tex, lambda tmp: Path(tmp).write_text(latex_table(frame, caption)))
    rel = lambda p: html.escape(p.relative_to(root).as_posix())  # noqa: E731
    return (html_table(frame, where) + f"<p class='dl'>This table as <a href='{rel(csv)}'>CSV</a> · "
            f"<a href='{rel(tex)}'>LaTeX</a></p>")
