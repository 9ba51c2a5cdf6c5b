"""The control scores of every temporal measure, for the report's "how to read".

Computed by the sweep with :func:`aaeval.metrics.controls.control_scores` and stored in its
``controls.json`` (never written by hand): a measure added to the registry appears here
with its scores, and a measure that misses a known answer shows it.
"""

from __future__ import annotations

import html
import math

from aaeval.sweeps.typed_json import decode_float
from aaeval.report.html_tables import Stored, shown
from aaeval.report.sweep_data import METRICS

__all__ = ["controls_html"]

#: A score this close to its known answer meets it (the controls are exact up to rounding).
TOLERANCE = 1e-9


def controls_html(stored: dict) -> str:
    """One table: a row per registered temporal measure, a column per control, each cell
    the measure's score on that control and, where the construction fixes one, the answer
    (``stored``: the sweep's ``controls.json``)."""
    CONTROLS, CONTROL_NOTES = stored["controls"], stored["notes"]  # noqa: N806 - the module's names, as stored
    rows: dict[str, dict[str, tuple[int, dict]]] = {}
    for i, r in enumerate(stored["scores"]):  # a number's stored row: its place in "scores"
        rows.setdefault(r["measure"], {})[r["control"]] = (i, r)
    head = "".join(f"<th title='{html.escape(CONTROL_NOTES[c])}'>{html.escape(c.replace('_', ' '))}</th>"
                   for c in CONTROLS)
    body = []
    for name, by_control in rows.items():
        metric = METRICS[name]
        cells = []
        for control in CONTROLS:
            i, r = by_control[control]
            score, expected = decode_float(r["score"]), decode_float(r["expected"])
            text = shown(score, Stored("controls.json", i, "score", metric.fmt)) if math.isfinite(score) else "n/a"
            if math.isfinite(expected):
                met = math.isfinite(score) and abs(score - expected) <= TOLERANCE
                answer = shown(expected, Stored("controls.json", i, "expected", metric.fmt))
                text += f" ({'=' if met else 'expected'} {answer}{'' if met else ' ✗'})"
            cells.append(f"<td class='num' data-measure='{html.escape(name)}' data-control='{control}'>{text}</td>")
        body.append(f"<tr><td>{html.escape(metric.title)} <code>{html.escape(name)}</code></td>{''.join(cells)}</tr>")
    notes = "; ".join(f"<i>{html.escape(c.replace('_', ' '))}</i>: {html.escape(CONTROL_NOTES[c])}" for c in CONTROLS)
    return (f"<p>Every temporal measure on controls whose right answer is known (a thin highlight drifting "
            f"0.15 px a frame, box-filtered exactly, is the truth; {notes}). In brackets the answer fixed by the "
            f"construction, where there is one; n/a: the measure has nothing to measure there.</p>"
            f"<table class='controls'><tr><th>measure</th>{head}</tr>{''.join(body)}</table>")
