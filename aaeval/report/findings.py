"""The findings at the top of the report: one ranked table per question, drawn from the sweep.

The sweep ranked every question's answers once (:mod:`aaeval.sweeps.summaries`:
``findings``, ``findings_questions``, ``findings_per_scene``), each value the mean of one
group's cells (``results.parquet``) or animations (``temporal.parquet``) of one spec by
:func:`~aaeval.sweeps.aggregate.per_spec`, the aggregation the group charts and the
specular and filters sections use, so a ranking reads the same wherever it appears. Each
number names where it is stored (``data-source``, ``data-row``, ``data-column``) and the
cells it aggregates (``data-from``, ``data-group``, ``data-spec``, ``data-agg``: the tests
recompute it), and links to the group's section.

Nothing is measured here: the sentence naming a question's leader is computed from the
table it sits on.
"""

from __future__ import annotations

import html
import math
import json

import pandas as pd

from aaeval.sweeps.record import noise_column
from aaeval.sweeps.summaries import QUESTIONS, Question
from aaeval.metrics.info import format_value
from aaeval.report.html_tables import Stored
from aaeval.report.sweep_data import METRICS, SweepData
from aaeval.metrics.agreement import EXACT_ROUNDING, PASS_FRACTION, SIGNIFICANCE, Truth, agrees
from aaeval.report.names import figure_stem

__all__ = ["Question", "QUESTIONS", "findings_section", "leader_sentence"]


def _fmt(column: str, value) -> str:
    metric = METRICS.get(column)
    if metric is not None:
        return metric.format(value)
    return format_value(value, ".4g")


def _title(column: str) -> str:
    metric = METRICS.get(column)
    return metric.title if metric is not None else {"ms_per_mpix": "ms per megapixel"}.get(column, column)


def leader_sentence(question: Question, table: pd.DataFrame, group: str) -> str:
    """One sentence from ``table`` (ranked, best first): the leader, its value, and by how much it
    leads the next method (another method, not the leader's own ladder), or that the two are
    tied. Where the column is an RMS metric with a z-test against the truth
    (:mod:`aaeval.metrics.agreement`), the two tie when both pass it: the truth cannot tell
    either from itself, nor so the two apart; otherwise, against a seeded truth, within its
    noise (a noise-free truth's error bound is no noise: there only float rounding ties)."""
    if table.empty:
        return f"{question.title}: no cell of this sweep answers it."
    first = table.iloc[0]
    title = _title(question.column)
    others = table[table["ladder"] != first["ladder"]]
    head = (f"{question.title} ({title}, group {group}): <b>{html.escape(first['label'])}</b> leads with "
            f"{_fmt(question.column, first['value'])}")
    if others.empty:
        return head + "; no other method was measured."
    second = others.iloc[0]
    a, b = float(first["value"]), float(second["value"])
    metric = METRICS.get(question.column)
    noise = first.get("noise", math.nan)
    seeded = _truth(first).kind == "seeded"
    resolvable = (question.table != "speed" and metric is not None and metric.target is None
                  and question.noise == "reference_noise_rmse" and question.column != "highlight_profile_flicker"
                  and seeded and math.isfinite(noise) and noise > 0)
    verdicts = (agrees(first.get("agreement", math.nan)), agrees(second.get("agreement", math.nan)))
    tested = None not in verdicts
    # values that differ by float rounding only (two exact methods' sums, 6e-15 apart) are equal
    rounding = abs(a - b) <= EXACT_ROUNDING * max(1.0, abs(a), abs(b))
    if rounding or (tested and all(verdicts)) or (not tested and resolvable and abs(b - a) < noise):
        why = "equal up to float rounding" if rounding else (
            f"both agree with the ground truth by its per-pixel z-test ({_z_test_words()})" if tested
            else f"they differ by less than the ground truth's noise ({noise:.3g})")
        return (f"{question.title} ({title}, group {group}): <b>{html.escape(first['label'])}</b> and "
                f"<b>{html.escape(second['label'])}</b> tie ({_fmt(question.column, a)} and "
                f"{_fmt(question.column, b)}: {why}).")
    if metric is not None and metric.target is not None:
        da, db = abs(a - metric.target), abs(b - metric.target)
        gap = f"{db - da:.3g} closer to {metric.target:g} than"
    elif a == 0 and b > 0:
        return head + (f" (none at all); the next method, <b>{html.escape(second['label'])}</b>, has "
                       f"{_fmt(question.column, b)}.")
    elif a > 0 and b > 0:
        ratio = b / a if not (metric is not None and metric.higher_is_better) else a / b
        gap = f"{ratio:.3g}x {'better than' if ratio >= 1 else 'against'}"
    else:
        gap = f"{abs(b - a):.3g} better than"
    tail = (f", {gap} the next method, <b>{html.escape(second['label'])}</b> "
            f"({_fmt(question.column, b)})")
    return head + tail + "."


def _truth(row) -> Truth:
    """The truth a findings row was judged against, as the sweep stored it."""
    kind = row.get("truth_kind", "") if hasattr(row, "get") else ""
    return Truth(kind if isinstance(kind, str) and kind else "unknown", float(row.get("truth_level", math.nan)))


def truth_html(table: pd.DataFrame) -> str:
    """The sentence under a findings table naming the truth it was judged against."""
    if table.empty or not str(table["reference"].iloc[0] if "reference" in table else ""):
        return ""
    truth = _truth(table.iloc[0])
    return (f"<p class='dl truth'>Judged against <code>{html.escape(str(table['reference'].iloc[0]))}</code> "
            f"({html.escape(truth.words('.3g'))}).</p>")


FINDINGS, PER_SCENE = "summaries/findings.parquet", "summaries/findings_per_scene.parquet"


def per_scene_html(question: Question, stored: pd.DataFrame) -> str:
    """A table of ``question``'s column and extras per scene (rows: specs in rank order; one
    column per scene and measure), each value one animation's (``stored``: the question's
    rows of the stored ``findings_per_scene`` summary)."""
    scenes = list(dict.fromkeys(stored["scene"]))
    if len(scenes) < 2:
        return ""
    columns = list(dict.fromkeys(stored["column"]))
    head = "".join(f"<th>{html.escape(_title(c))}, {html.escape(s)}</th>" for s in scenes for c in columns)
    body = []
    for spec, mine in stored.groupby("spec", sort=False):
        cells = []
        for s in scenes:
            for c in columns:
                at = mine[(mine["scene"] == s) & (mine["column"] == c)]
                if at.empty:
                    cells.append("<td></td>")
                    continue
                i = at.index[0]
                where = Stored(PER_SCENE, i, "value", _format_of(c))
                cells.append(f"<td class='num' {where.attributes()}>{html.escape(_fmt(c, at.at[i, 'value']))}</td>")
        label = Stored(PER_SCENE, mine.index[0], "label")
        body.append(f"<tr><td {label.attributes()}>{html.escape(mine['label'].iloc[0])}</td>{''.join(cells)}</tr>")
    return ("<p class='dl'>Per scene (one animation each):</p><table class='findings per-scene'>"
            f"<tr><th>method (options)</th>{head}</tr>{''.join(body)}</table>")


def _format_of(column: str) -> str:
    metric = METRICS.get(column)
    return metric.fmt if metric is not None else ".4g"


def _z_test_words() -> str:
    return (f"significance {SIGNIFICANCE:g} with a Sidak correction over the pixels, at least "
            f"{PASS_FRACTION:.2%} of the pixels passing")


def _cell(row: int, column: str, value, *, fmt: str, href: str, origin: str = "") -> str:
    """A number of a findings table: where it is stored, and (``origin``) the cells it is
    the aggregate of, for the tests to recompute it."""
    where = Stored(FINDINGS, row, column, fmt)
    text = format_value(value, fmt)
    link = f"<a href='{html.escape(href)}'>{html.escape(text)}</a>" if href else html.escape(text)
    return f"<td class='num' {where.attributes()}{origin}>{link}</td>"


def _origin(source: str, group: str, spec: str, column: str, how: str) -> str:
    return (f" data-from='{html.escape(source)}' data-group='{html.escape(group)}' data-spec='{html.escape(spec)}' "
            f"data-from-column='{html.escape(column)}' data-agg='{how}'")


_SOURCES = {"results": "results.parquet", "temporal": "temporal.parquet", "speed": "speed.parquet"}


def _question_html(q: Question, groups: list[str], found: pd.DataFrame, per_scene: pd.DataFrame,
                   speed_note: str) -> list[str]:
    """A question's block: for each group that measured it, its leader sentence, the truth it
    was judged against and its ranked table (``found``: the question's stored rows)."""
    parts = [f"<h3 id='finding-{q.key}'>{html.escape(q.title)}</h3>"]
    if not groups:
        return parts + [f"<p>Not measured in this sweep ({html.escape(q.what)}).</p>"]
    parts.append(f"<p class='dl'>{html.escape(q.what)}. {speed_note if q.table == 'speed' else ''}</p>")
    if len(groups) > 1 and q.table != "speed":
        links = ", ".join(f"<a href='#{figure_stem(g)}'>{html.escape(g)}</a>" for g in groups)
        parts.append(f"<p class='dl'>Measured in {len(groups)} groups ({links}): each group's own ranking follows, "
                     "each against its own truth.</p>")
    for group in groups:
        table = found[found["group"] == group] if not found.empty else found
        scenes = per_scene[per_scene["group"] == group] if not per_scene.empty else per_scene
        parts += _group_answer(q, group, table, scenes)
    return parts


def _noise_heading(q: Question, table: pd.DataFrame, noise: str) -> str:
    """The heading of the column beside each number: the truth's own value of that kind."""
    if q.table == "speed":
        return "spread over scenes and rounds (fastest-slowest)"
    if q.noise == "reference_sum_variation":
        return "ground truth's own sum variation"
    truth = _truth(table.iloc[0]) if len(table) else Truth("unknown", math.nan)
    pixels = f" ({_title(q.column)} pixels)" if noise == noise_column(q.column) else ""
    if truth.kind == "bounded" and noise == "reference_noise_rmse":
        return "exact truth's error bound RMS"
    if truth.noise_free:
        return f"ground truth noise RMS{pixels} (exact: none)"
    return f"ground truth noise RMS{pixels}"


def _group_answer(q: Question, group: str, table: pd.DataFrame, per_scene: pd.DataFrame) -> list[str]:
    parts = [f"<p>{leader_sentence(q, table, group)}</p>"]
    parts.append(truth_html(table))
    href = "#speed" if q.table == "speed" else f"#{figure_stem(group)}"
    extras = [(t, c) for t, c in q.extra if c in table]
    noise = table["noise_column"].iloc[0] if len(table) else q.noise
    tested = table["agreement_text"].astype(bool).any() if len(table) else False
    head = ["rank", "method (options)", _title(q.column)] + [_title(c) for _, c in extras]
    head.append(_noise_heading(q, table, noise))
    if tested:
        head.append("against the truth: per-pixel z-test")
    rows = []
    for i, r in table.iterrows():
        how = r["how"]
        cells = [f"<td {Stored(FINDINGS, i, 'rank').attributes()}>{int(r['rank'])}</td>",
                 f"<td {Stored(FINDINGS, i, 'label').attributes()}>{html.escape(r['label'])}</td>",
                 _cell(i, "value", r["value"], fmt=_format_of(q.column), href=href,
                       origin=_origin(_SOURCES[q.table], group, r["spec"], q.column, how))]
        for t, c in extras:
            cells.append(_cell(i, c, r[c], fmt=_format_of(c), href=href,
                               origin=_origin(_SOURCES[t], group, r["spec"], c, "mean")))
        if q.table == "speed":
            cells.append(_spread(i, r) if math.isfinite(r["spread_min"]) else "<td></td>")
        elif math.isfinite(r["noise"]):
            cells.append(_cell(i, "noise", r["noise"], fmt=".2e", href=""))
        else:
            cells.append("<td></td>")
        if tested:
            text = r["agreement_text"]
            cells.append(f"<td class='num' {Stored(FINDINGS, i, 'agreement_text').attributes()}>{html.escape(text)}</td>"
                         if text else "<td></td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    parts.append(f"<table class='findings' data-group='{html.escape(group)}'><tr>"
                 + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>" + "".join(rows) + "</table>")
    if q.per_scene and not per_scene.empty:
        parts.append(per_scene_html(q, per_scene))
    return [p for p in parts if p]


def _spread(i: int, r) -> str:
    low = Stored(FINDINGS, i, "spread_min", ".4g")
    high = Stored(FINDINGS, i, "spread_max", ".4g")
    return (f"<td class='num'><span {low.attributes()}>{r['spread_min']:.4g}</span>-"
            f"<span {high.attributes()}>{r['spread_max']:.4g}</span></td>")


def findings_section(data: SweepData, *, speed_note: str = "") -> str:
    """The findings: per question a computed sentence and a ranked table, drawn from the
    stored ``findings`` summaries; each number names where it is stored and links to its group."""
    found, questions = data.summary("findings"), data.summary("findings_questions")
    per_scene = data.summary("findings_per_scene")
    parts = ["<h2 id='findings'>Findings</h2>",
             "<p class='note'>Generated from <a href='results.parquet'>results.parquet</a>, "
             "<a href='temporal.parquet'>temporal.parquet</a>"
             + (" and <a href='speed.parquet'>speed.parquet</a>" if not data.speed.empty else "") + ": every "
             "number is the mean of one group's cells (or animations) of one method and option, the same value the "
             "group's charts and tables show; it links to that group. Rows are methods with their options (a ladder "
             "is several rows), best first. Where several groups measured a question, each group's own ranking is "
             "shown. Each table names the truth it was judged against, its group's reference: a seeded render (Mitsuba "
             "at high spp) with its noise, RMS per pixel and channel measured seed to seed on the metric's own pixels "
             "where the metric is an RMS over some of them, beside each number; or a noise-free exact render, whose "
             "only uncertainty is float rounding and, for exact shading, the quadrature's error bound (a bound, not "
             "noise: no error is divided by it, and agreeing with it means being within the bound plus rounding). "
             "Whether a method agrees with the truth, and so whether two methods tie, is a per-pixel z-test where "
             f"the table shows one ({_z_test_words()}; on a pixel an edge crosses, the noise is one scale pooled over "
             "the metric's edge pixels times the range of the colours meeting there, per channel; elsewhere the "
             "noise of the other pixels). Against a noise-free truth a seeded method, Mitsuba's cross-check row among them, is tested within its own "
             "noise, measured as the truth's would be (a second render with the next seed). Where no test applies, "
             "differences smaller than the noise are not resolved.</p>"]
    answered = questions.set_index("question") if not questions.empty else questions
    for q in QUESTIONS:
        group = answered.at[q.key, "group"] if q.key in answered.index else None
        groups = [group, *json.loads(answered.at[q.key, "also"])] if isinstance(group, str) else []
        table = found[found["question"] == q.key] if not found.empty else found
        scenes = per_scene[per_scene["question"] == q.key] if not per_scene.empty else per_scene
        parts.extend(_question_html(q, groups, table, scenes, speed_note))
    return "\n".join(parts)
