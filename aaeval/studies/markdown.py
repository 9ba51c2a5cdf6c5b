"""Markdown of the generated section: numbers, names and prose from the files written safely
(markup, study markers and table bars escaped), tables, and the line stating whether an
expectation of ``study.toml`` holds."""

from __future__ import annotations

import html
import math
import re
from typing import Any


def verdict(checks: list[bool], expectation: str, ok: bool, measured: str = "") -> list[str]:
    """One line stating an expectation of study.toml and whether the results bear it out;
    the expectation is the study's prediction, the verdict and ``measured`` come from the data."""
    checks.append(bool(ok))
    return ["", f"Expected: {expectation}. **{'Holds' if ok else 'Does not hold'}**{measured}."]


def quoted(labels: list[str]) -> str:
    return ", ".join(md_code(m) for m in labels)


def fmt(x: float, spec: str = ".4g") -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    return format(float(x), spec)


#: Text written as it is inside a code span: names as configs and scene files write them.
_PLAIN = re.compile(r"[\w .:=,@+/()%#-]*")


def md_code(text: Any) -> str:
    """A name from the config or the results (a method, a scene, a path) as markdown code; a name
    holding markup, markers or table bars is written as escaped HTML instead."""
    text = " ".join(str(text).split())
    if _PLAIN.fullmatch(text):
        return f"`{text}`"
    return "<code>" + html.escape(text).replace("|", "&#124;").replace("`", "&#96;") + "</code>"


def md_text(text: Any) -> str:
    """Prose from study.toml or the results (a title, a note) on one line, markup escaped."""
    return html.escape(" ".join(str(text).split()), quote=False).replace("|", "&#124;")


def md_table(header: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header), *("| " + " | ".join(r) + " |" for r in rows)]
