"""The report's tables: each shown as HTML and written beside the page as CSV and LaTeX
(``DIR/tables/<name>.csv``, ``.tex``), ready for a paper."""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.fileio import atomic_write

__all__ = ["html_table", "write_table", "latex_table", "fmt"]


def fmt(value) -> str:
    """A cell as text: 4 significant digits for floats, nothing for missing values."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, (float, np.floating)):
        return f"{value:.4g}"
    return str(value)


def _numeric(v) -> bool:
    return isinstance(v, (int, float, np.number)) and not isinstance(v, (bool, np.bool_))


def html_table(frame: pd.DataFrame) -> str:
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
    body = []
    for row in frame.itertuples(index=False):
        cells = "".join(f"<td class='num'>{html.escape(fmt(v))}</td>" if _numeric(v)
                        else f"<td>{html.escape(fmt(v))}</td>" for v in row)
        body.append(f"<tr>{cells}</tr>")
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


def write_table(frame: pd.DataFrame, directory: Path, name: str, root: Path, caption: str = "") -> str:
    """Write ``name.csv`` and ``name.tex`` under ``directory``; return the HTML table with
    links to both (relative to the page in ``root``)."""
    directory = Path(directory)
    csv, tex = directory / f"{name}.csv", directory / f"{name}.tex"
    atomic_write(csv, lambda tmp: frame.to_csv(tmp, index=False))
    atomic_write(tex, lambda tmp: Path(tmp).write_text(latex_table(frame, caption)))
    rel = lambda p: html.escape(p.relative_to(root).as_posix())  # noqa: E731
    return (html_table(frame) + f"<p class='dl'>This table as <a href='{rel(csv)}'>CSV</a> · "
            f"<a href='{rel(tex)}'>LaTeX</a></p>")
