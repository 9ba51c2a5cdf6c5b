"""The findings at the top of the report: one ranked table per question, read from the results.

Every number here is a value of ``results.parquet`` (one row per cell) or
``temporal.parquet`` (one row per animation), averaged over one group's cells of one spec
by :func:`per_spec`; that one aggregation is also what the group charts and the specular
and filters sections draw, so a ranking reads the same wherever it appears. Each number
carries ``data-*`` attributes naming the table, group, spec, column and aggregation it
comes from (the tests recompute it from the parquet files) and links to the group's
section and to its CSV.

Nothing is measured here: the sentence naming a question's leader is computed from the
table it sits on.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass

import pandas as pd

from aaeval.experiments.record import agreement_column, noise_column
from aaeval.metrics.info import format_value
from aaeval.report.sweep_data import METRICS
from aaeval.metrics.agreement import PASS_FRACTION, SIGNIFICANCE, agrees
from aaeval.report.names import figure_stem

__all__ = ["Question", "QUESTIONS", "per_spec", "ranked", "findings_section", "leader_sentence", "answering_groups"]


@dataclass(frozen=True)
class Question:
    """One question of the findings: which column of which table answers it, where."""

    key: str
    title: str
    table: str  # "results" or "temporal" (or "speed": the speed pass)
    column: str
    groups: tuple[str, ...]  # groups that answer it, first present wins
    extra: tuple[tuple[str, str], ...] = ()  # further columns beside it: (table, column)
    what: str = ""
    noise: str = "reference_noise_rmse"  # the ground truth's own value of this kind, beside each number
    per_scene: bool = False  # also a table of each scene's values: a mean over unlike scenes hides them


QUESTIONS = (
    Question("edges", "Edge aliasing", "results", "edge_rmse", ("edge-aliasing", "khan-figures-moving"),
             what="error over the pixels a visible edge crosses, mean over scenes and frames"),
    Question("highlights", "Highlight aliasing", "results", "highlight_rmse", ("specular-thin", "specular"),
             extra=(("temporal", "highlight_bias"), ("temporal", "highlight_profile_flicker")),
             what="error over the highlight pixels, mean over scenes and frames; beside it the highlight's bias "
                  "(time-average of its energy error) and flicker (what is left, frame to frame)"),
    Question("temporal", "Temporal stability", "temporal", "flicker", ("edge-aliasing", "khan-figures-moving"),
             extra=(("temporal", "temporal_bias"),),
             what="flicker of the error over each animation (the error minus its time-average), mean over "
                  "animations; beside it the bias (the time-average)"),
    Question("highlight-flicker", "Temporal stability of highlights", "temporal", "highlight_profile_flicker",
             ("specular-thin", "specular"), extra=(("temporal", "highlight_bias"),),
             what="spread over frames of each highlight cross-section's energy error, relative, mean over animations; "
                  "beside it the highlight's bias"),
    Question("sums", "Sum invariance", "temporal", "sum_variation", ("invariance", "edge-aliasing"),
             extra=(("temporal", "sum_bias"),), per_scene=True,
             what="(max - min) / mean of the image's intensity sum while the scene moves, mean over animations; "
                  "beside it the sum's bias against the exact sum in the typical frame (median over frames), and "
                  "the ground truth's own variation", noise="reference_sum_variation"),
    Question("cost", "Cost", "speed", "ms_per_mpix", ("speed",),
             what="render time per megapixel in the speed pass (one worker, interleaved repeats after a "
                  "warm-up), median over its scenes and rounds"),
    Question("cost-shading", "Cost of specular anti-aliasing", "speed", "ms_per_mpix", ("speed-1",),
             what="render time per megapixel of every specular method in the speed pass's second table, median "
                  "over its scenes and rounds"),
)


def per_spec(frame: pd.DataFrame, group: str, column: str, *, how: str = "mean",
             noise: str = "reference_noise_rmse") -> pd.DataFrame:
    """One row per spec of ``group``: ``column`` aggregated over its rows (``how``: mean or
    median) with the ground truth's noise beside it; columns spec, label, method, options,
    value, noise, rows, agreement (the mean z-test pass fraction of an RMS metric against
    the truth, :mod:`aaeval.metrics.agreement`; NaN for other columns). The one
    aggregation behind every ranking of the page."""
    columns = ["spec", "label", "method", "options", "ladder", "value", "noise", "rows", "agreement"]
    rows = frame[(frame["group"] == group)] if "group" in frame else frame.iloc[:0]
    if "error" in rows:
        rows = rows[rows["error"].isna()]
    if column not in rows or rows.empty:
        return pd.DataFrame(columns=columns)
    out = []
    for spec, r in rows.groupby("spec", sort=False):
        values = pd.to_numeric(r[column], errors="coerce")
        if not values.notna().any():
            continue
        value = float(values.median() if how == "median" else values.mean())
        truth = pd.to_numeric(r[noise], errors="coerce") if noise in r else pd.Series(dtype=float)
        passed = pd.to_numeric(r[agreement_column(column)], errors="coerce") \
            if agreement_column(column) in r else pd.Series(dtype=float)
        out.append({"spec": spec, "label": r["label"].iloc[0], "method": r["method"].iloc[0],
                    "options": r["options"].iloc[0] if "options" in r else "{}",
                    "ladder": r["ladder"].iloc[0] if "ladder" in r else spec, "value": value,
                    "noise": float(truth.mean()) if truth.notna().any() else math.nan, "rows": int(values.notna().sum()),
                    "agreement": float(passed.mean()) if passed.notna().any() else math.nan})
    return pd.DataFrame(out, columns=columns)


def _better_first(column: str) -> callable:
    metric = METRICS.get(column)
    if metric is not None and metric.target is not None:
        return lambda v: abs(v - metric.target)
    if metric is not None and metric.higher_is_better:
        return lambda v: -v
    return lambda v: v


def ranked(frame: pd.DataFrame, group: str, column: str, *, how: str = "mean",
           noise: str = "reference_noise_rmse") -> pd.DataFrame:
    """:func:`per_spec`, best first (by the metric's direction), ties kept in spec order."""
    table = per_spec(frame, group, column, how=how, noise=noise)
    if table.empty:
        return table
    key = _better_first(column)
    return table.assign(_k=table["value"].map(key)).sort_values("_k", kind="stable").drop(columns="_k") \
        .reset_index(drop=True)


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
    either from itself, nor so the two apart; otherwise within the ground truth's noise."""
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
    resolvable = (question.table != "speed" and metric is not None and metric.target is None
                  and question.noise == "reference_noise_rmse" and question.column != "highlight_profile_flicker"
                  and math.isfinite(noise) and noise > 0)
    verdicts = (agrees(first.get("agreement", math.nan)), agrees(second.get("agreement", math.nan)))
    tested = None not in verdicts
    # values that differ by float rounding only (two exact methods' sums, 6e-15 apart) are equal
    rounding = abs(a - b) <= _ROUNDING * max(1.0, abs(a), abs(b))
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


_ROUNDING = 1e-12


def per_scene_html(question: Question, frame: pd.DataFrame, group: str, order: list[str]) -> str:
    """A table of ``question``'s column and extras per scene of ``group`` (rows: specs in
    ``order``; one column per scene and measure), each value one animation's."""
    rows = frame[frame["group"] == group]
    scenes = list(dict.fromkeys(rows["scene"]))
    if len(scenes) < 2:
        return ""
    columns = [question.column] + [c for t, c in question.extra if t == question.table and c in rows]
    head = "".join(f"<th>{html.escape(_title(c))}, {html.escape(s)}</th>" for s in scenes for c in columns)
    body = []
    for spec in order:
        mine = rows[rows["spec"] == spec]
        if mine.empty:
            continue
        cells = []
        for s in scenes:
            one = mine[mine["scene"] == s]
            for c in columns:
                v = pd.to_numeric(one[c], errors="coerce").mean() if not one.empty else math.nan
                cells.append(f"<td class='num' data-source='temporal.parquet' data-group='{html.escape(group)}' "
                             f"data-spec='{html.escape(spec)}' data-scene='{html.escape(s)}' "
                             f"data-column='{html.escape(c)}'>{html.escape(_fmt(c, v))}</td>")
        body.append(f"<tr><td>{html.escape(mine['label'].iloc[0])}</td>{''.join(cells)}</tr>")
    return ("<p class='dl'>Per scene (one animation each):</p><table class='findings per-scene'>"
            f"<tr><th>method (options)</th>{head}</tr>{''.join(body)}</table>")


def _z_test_words() -> str:
    return (f"significance {SIGNIFICANCE:g} with a Sidak correction over the pixels, at least "
            f"{PASS_FRACTION:.2%} of the pixels passing")


def _agreement_cell(fraction: float) -> str:
    verdict = agrees(fraction)
    if verdict is None:
        return "<td></td>"
    word = "agrees" if verdict else "differs"
    return f"<td class='num'>{word} ({fraction:.2%} pass)</td>"


def _cell(value: str, *, source: str, group: str, spec: str, column: str, how: str, href: str) -> str:
    attrs = (f"data-source='{html.escape(source)}' data-group='{html.escape(group)}' "
             f"data-spec='{html.escape(spec)}' data-column='{html.escape(column)}' data-agg='{how}'")
    return f"<td class='num' {attrs}><a href='{html.escape(href)}'>{html.escape(value)}</a></td>"


def answering_groups(question: Question, tables: dict[str, pd.DataFrame]) -> list[str]:
    """Every group that measured ``question``'s column, the question's own groups first (in
    their order), then the others in the order of the table: whatever a group is named, what
    it measured answers the questions of that measure."""
    frame = tables.get(question.table)
    if frame is None or frame.empty or question.column not in frame:
        return []
    values = pd.to_numeric(frame[question.column], errors="coerce")
    measured = list(dict.fromkeys(frame.loc[values.notna(), "group"]))
    if question.table == "speed":  # each speed pass is named by its place, and each is its own question
        return [g for g in question.groups if g in measured]
    return [g for g in question.groups if g in measured] + [g for g in measured if g not in question.groups]


def _pick_group(question: Question, tables: dict[str, pd.DataFrame]) -> str | None:
    groups = answering_groups(question, tables)
    return groups[0] if groups else None


def findings_section(results: pd.DataFrame, temporal: pd.DataFrame, speed: pd.DataFrame | None = None, *,
                     speed_note: str = "") -> str:
    """The findings: per question a computed sentence and a ranked table whose numbers link to
    where they come from. ``speed``: the speed pass's table (``speed.parquet``), if any."""
    tables = {"results": results, "temporal": temporal}
    if speed is not None and not speed.empty:
        # each [[speed]] table is its own group: "speed" (the first), "speed-1", ...
        ladders = dict(zip(results["spec"], results["ladder"])) if "ladder" in results else {}
        tables["speed"] = speed.assign(group=speed["pass"].map(lambda i: "speed" if i == 0 else f"speed-{i}"),
                                       ladder=[ladders.get(spec, spec) for spec in speed["spec"]])
    parts = ["<h2 id='findings'>Findings</h2>",
             "<p class='note'>Generated from <a href='results.parquet'>results.parquet</a>, "
             "<a href='temporal.parquet'>temporal.parquet</a>"
             + (" and <a href='speed.parquet'>speed.parquet</a>" if "speed" in tables else "") + ": every "
             "number is the mean of one group's cells (or animations) of one method and option, the same value the "
             "group's charts and tables show; it links to that group. Rows are methods with their options (a ladder "
             "is several rows), best first. The ground truth's own noise (RMS per pixel and channel, measured seed to "
             "seed, on the metric's own pixels where the metric is an RMS over some of them) stands beside each. "
             "Whether a method agrees with the truth, and so whether two methods tie, is a per-pixel z-test where "
             f"the table shows one ({_z_test_words()}; on a pixel an edge crosses, the noise is one scale pooled over "
             "the metric's edge pixels times the range of the colours meeting there, per channel; elsewhere the "
             "noise of the other pixels). Against a noise-free truth (an exact reference: its noise is 0, or the "
             "quadrature's bound) a seeded method, Mitsuba's cross-check row among them, is tested within its own "
             "noise, measured as the truth's would be (a second render with the next seed). Where no test applies, "
             "differences smaller than the noise are not resolved.</p>"]
    for q in QUESTIONS:
        group = _pick_group(q, tables)
        parts.append(f"<h3 id='finding-{q.key}'>{html.escape(q.title)}</h3>")
        if group is None:
            parts.append(f"<p>Not measured in this sweep ({html.escape(q.what)}).</p>")
            continue
        how = "median" if q.table == "speed" else "mean"
        # an RMS metric's noise is the truth's on that metric's own pixels, with the same reduction
        own_noise = noise_column(q.column)
        noise = own_noise if q.table == "results" and own_noise in tables["results"] else q.noise
        tested = q.table == "results" and agreement_column(q.column) in tables["results"]
        table = ranked(tables[q.table], group, q.column, how=how, noise=noise)
        parts.append(f"<p>{leader_sentence(q, table, group)}</p>")
        parts.append(f"<p class='dl'>{html.escape(q.what)}. {speed_note if q.table == 'speed' else ''}</p>")
        also = answering_groups(q, tables)[1:]
        if also and q.table != "speed":
            links = ", ".join(f"<a href='#{figure_stem(g)}'>{html.escape(g)}</a>" for g in also)
            parts.append(f"<p class='dl'>Also measured in group(s) {links}: their tables rank the same column.</p>")
        href = "#speed" if q.table == "speed" else f"#{figure_stem(group)}"
        extras = [(t, c) for t, c in q.extra if t in tables and c in tables[t]]
        extra_values = {(t, c): per_spec(tables[t], group, c).set_index("spec")["value"] for t, c in extras}
        head = ["rank", "method (options)", _title(q.column)] + [_title(c) for _, c in extras]
        head.append("spread over scenes and rounds (fastest-slowest)" if q.table == "speed" else
                    "ground truth's own sum variation" if q.noise == "reference_sum_variation" else
                    f"ground truth noise RMS ({_title(q.column)} pixels)" if noise == own_noise else
                    "ground truth noise RMS")
        if tested:
            head.append("against the truth: per-pixel z-test")
        rows = []
        source = {"results": "results.parquet", "temporal": "temporal.parquet", "speed": "speed.parquet"}
        for i, r in enumerate(table.itertuples(), 1):
            cells = [f"<td>{i}</td>", f"<td>{html.escape(r.label)}</td>",
                     _cell(_fmt(q.column, r.value), source=source[q.table], group=group, spec=r.spec,
                           column=q.column, how=how, href=href)]
            for t, c in extras:
                v = extra_values[(t, c)].get(r.spec, math.nan)
                cells.append(_cell(_fmt(c, v), source=source[t], group=group, spec=r.spec, column=c, how="mean",
                                   href=href))
            if q.table == "speed":
                spread = tables["speed"]
                s = pd.to_numeric(spread[(spread["group"] == group) & (spread["spec"] == r.spec)]["ms_per_mpix"],
                                  errors="coerce").dropna()
                cells.append(f"<td class='num'>{s.min():.4g}-{s.max():.4g}</td>" if len(s) else "<td></td>")
            else:
                cells.append(f"<td class='num'>{'' if not math.isfinite(r.noise) else f'{r.noise:.2e}'}</td>")
            if tested:
                cells.append(_agreement_cell(r.agreement))
            rows.append("<tr>" + "".join(cells) + "</tr>")
        parts.append("<table class='findings'><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>"
                     + "".join(rows) + "</table>")
        if q.per_scene:
            parts.append(per_scene_html(q, tables[q.table], group, list(table["spec"])))
    return "\n".join(parts)
