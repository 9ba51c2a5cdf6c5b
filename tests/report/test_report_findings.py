"""One answer per question. The findings come from the tables, the failure count means
something, and the highlight flicker ranks alike in the findings, the group chart and the
specular section."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pandas as pd
import pytest

from aaeval.sweeps.table import read_table
from aaeval.metrics import METRICS, format_value
from tests.helpers.findings_util import findings_report

# one worker builds the module's sweep fixture once (pyproject's --dist loadgroup);
# split across two workers each would build it
# slow: a sweep and its report built first (about 7 s)
pytestmark = [pytest.mark.xdist_group("report_findings"), pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return findings_report(tmp_path_factory)


def _page(out):
    return (out / "index.html").read_text()


def _findings(text):
    return text[text.index("<h2 id='findings'>"):text.index("<h2 id='how-to-read'>")]


def test_findings_come_first(out):
    text = _page(out)
    first_h2 = re.search(r"<h2 id='([^']+)'", text).group(1)
    assert first_h2 == "findings"
    for key in ("edges", "highlights", "temporal", "highlight-flicker", "sums", "cost"):
        assert f"id='finding-{key}'" in text


def test_every_number_of_the_findings_is_found_in_the_tables(out):
    tables = {"results.parquet": read_table(out / "results.parquet"),
              "temporal.parquet": read_table(out / "temporal.parquet"),
              "speed.parquet": pd.read_parquet(out / "speed.parquet")}
    tables["speed.parquet"]["group"] = ["speed" if p == 0 else f"speed-{p}" for p in tables["speed.parquet"]["pass"]]
    # the stored findings table's value is looked up by tests/report/test_report_numbers.py;
    # here it is recomputed from the cells it aggregates (data-from: their table)
    cells = re.findall(r"<td class='num' data-source='[^']+' data-row='\d+' data-column='[^']+' data-fmt='[^']+' "
                       r"data-from='([^']+)' data-group='([^']+)' data-spec='([^']+)' "
                       r"data-from-column='([^']+)' data-agg='(\w+)'><a href='([^']+)'>([^<]+)</a></td>",
                       _findings(_page(out)))
    assert len(cells) >= 20
    for source, group, spec, column, agg, href, shown in cells:
        frame = tables[source]
        rows = frame[(frame["group"] == group) & (frame["spec"] == spec)]
        if "error" in rows:
            rows = rows[rows["error"].isna()]
        values = pd.to_numeric(rows[column], errors="coerce").dropna()
        assert len(values), (source, group, spec, column)
        value = values.median() if agg == "median" else values.mean()
        fmt = METRICS[column].fmt if column in METRICS else ".4g"
        assert shown == format_value(value, fmt), (group, spec, column, shown, value)
        assert href.startswith("#")
        assert f"id='{href[1:]}'" in _page(out)


def test_each_question_names_its_leader_from_its_own_table(out):
    text = _findings(_page(out))
    for block in text.split("<h3 ")[1:]:
        if "Not measured" in block:
            continue
        leader = re.search(r"leads with| tie \(", block)
        assert leader, block[:200]
        first_row = re.search(r"<tr><td[^>]*>1</td><td[^>]*>([^<]+)</td>", block).group(1)
        assert f"<b>{first_row}</b> leads with" in block or f"<b>{first_row}</b> and <b>" in block


def _flicker_order_from_chart(out, group, metric):
    """The specs of the group's temporal chart ordered by the width of their bars in ``metric``'s panel."""
    manifest = json.loads((out / "manifest.json").read_text())
    names = [m for m in manifest["group_temporal"][group]]
    temporal = read_table(out / "temporal.parquet")
    names = [m for m in names if m in temporal and temporal[temporal["group"] == group][m].notna().any()]
    panel = names.index(metric)
    from aaeval.report.names import figure_stem

    svg = (out / "figures" / f"{figure_stem(group)}_temporal.svg").read_text()
    bars = re.findall(r'<g id="(method=[^"]+)">\s*<path d="M ([\d.]+) [\d.]+\s*L ([\d.]+) ', svg)
    seen: dict[str, int] = {}
    widths = {}
    for gid, x0, x1 in bars:
        k = seen.get(gid, 0)
        seen[gid] = k + 1
        if k == panel:
            widths[gid] = float(x1) - float(x0)
    return [gid for gid, _ in sorted(widths.items(), key=lambda kv: kv[1])]


def _gid(spec_label):
    from aaeval.renderers import resolve

    method, options = resolve(spec_label)
    options = {k: v for k, v in options.items()}
    return f"method={method.name};options=" + ",".join(f"{k}={options[k]}" for k in sorted(options))


def test_highlight_flicker_ranks_alike_in_findings_chart_and_section(out):
    text = _page(out)
    block = text[text.index("id='finding-highlight-flicker'"):text.index("id='finding-sums'")]
    findings = re.findall(r"<tr><td[^>]*>\d+</td><td[^>]*>([^<]+)</td>", block)
    section = text[text.index("<h2 id='specular'>"):]
    table = section[section.index("<table class='specular' data-group='specular'>"):]
    table = table[:table.index("</table>")]
    specular = re.findall(r"<tr><td[^>]*>([^<]+)</td>", table)
    assert findings == specular and len(findings) == 3
    chart = _flicker_order_from_chart(out, "specular", "highlight_profile_flicker")
    assert chart == [_gid(label) for label in findings]
    # bias and flicker are two columns, in the findings and in the section
    assert "hl bias (time-avg energy)" in block and "hl bias (time-avg energy)" in table


def test_no_exact_cell_fails_and_filters_are_judged_through_their_own_filter(out):
    from aaeval.renderers import METHODS, resolve
    from aaeval.sweeps.aggregate import failed_cells

    results = read_table(out / "results.parquet")
    manifest = json.loads((out / "manifest.json").read_text())
    shaded = {d for d, s in manifest["scenes"].items() if "shaded" in s["document"]}
    failed = failed_cells(results, "rmse", manifest["fail_above"], shaded)
    exact = results["method"].map(lambda m: METHODS[m].exact)
    assert not failed[exact].any()
    assert failed.any()  # point sampling does fail: the count means something
    filters = results[results["group"] == "filters"]
    for spec, reference in zip(filters["spec"], filters["reference"]):
        assert resolve(spec)[1].get("filter", "box") == resolve(reference)[1].get("filter", "box"), (spec, reference)
    text = _page(out)
    assert f"{int(failed.sum())} failed by the definition" in text


def test_the_report_package_defines_no_measure():
    found = subprocess.run(["grep", "-rn", r"def .*rmse\|def .*flicker", str(ROOT / "aaeval" / "report")],
                           capture_output=True, text=True).stdout
    assert found == ""


def test_the_speed_chart_says_one_worker_and_draws_the_pareto_front(out):
    text = _page(out)
    speed = text[text.index("<h2 id='speed'>"):]
    assert "one worker" in speed and "Pareto front" in speed
    assert "catmull / skia = " in speed  # catmull declares skia its speed baseline
    svg = (out / "figures" / "speed_accuracy_0.svg").read_text()
    assert "Pareto front" in svg


def test_a_copied_sweep_folder_gives_the_same_page(out, tmp_path, monkeypatch):
    """The report reads only the sweep folder: copied elsewhere and drawn from a directory with
    no configs/ and no scene files, it writes the same page (but for the time it was generated),
    the same tables, viewer data and PNG figures."""
    import shutil

    from aaeval.report import write_report

    copy = tmp_path / "copy"
    shutil.copytree(out, copy, ignore=shutil.ignore_patterns("index.html", "figures", "tables", "viewer"))
    monkeypatch.chdir(tmp_path)
    assert not (tmp_path / "configs").exists() and not list(tmp_path.glob("*.toml"))
    write_report(copy, formats=("png", "svg"))  # as findings_report drew the original
    generated = re.compile(r"Generated \d{4}-\d\d-\d\d \d\d:\d\d UTC")
    assert generated.sub("", (copy / "index.html").read_text()) == generated.sub("", (out / "index.html").read_text())
    for folder, pattern in (("tables", "*"), ("viewer", "*"), ("figures", "*.png")):  # SVG ids are random salts
        originals = sorted((out / folder).glob(pattern))
        assert originals and [p.name for p in sorted((copy / folder).glob(pattern))] == [p.name for p in originals]
        for p in originals:
            assert (copy / folder / p.name).read_bytes() == p.read_bytes(), p.name
