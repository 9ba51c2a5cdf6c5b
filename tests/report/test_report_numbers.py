"""Every number the page shows is found in the tables the sweep stored.

Each table cell and each marked number of a caption names the file of the sweep folder, the
row and the column it shows (``data-source``, ``data-row``, ``data-column``, and
``data-fmt`` where it is not written as :func:`aaeval.report.html_tables.fmt` writes it).
These tests look every one up in the stored file, then check that nothing else in a table
cell, a figure caption or a reference statement is a number: what is left once the marked
numbers and the names of groups, scenes, methods and references are taken out holds no
digit but the fixed words listed here, which define the measures rather than report them.
"""

from __future__ import annotations

import html
import json
import re
from functools import lru_cache
from pathlib import Path

import pandas as pd
import pytest

from aaeval.metrics.info import format_value
from aaeval.report.html_tables import fmt
from tests.helpers.findings_util import findings_report
from tests.helpers.report_util import small_report

# digits of the page's own definitions: how a measure or a figure is defined, never a result
FIXED_WORDS = ("sqrt 2", "1 is right", "its frame 0", "modulo 1 px", "256 x 256", "bias**2 + flicker**2",
               "cos^160", "Maximum[160]/Maximum[n']", "figure 2", "figure 3", "P = 0.999", "frame 0:",
               "4096 spp", "exceeds 0.02", "seed 1 against seed 0",
               "noise 0")  # an exact reference: no sampling noise, by what it is


_MARKED = re.compile(r"<(td|span)([^>]*\sdata-source='[^']*'[^>]*)>(.*?)</\1>", re.S)


# each page on the worker that builds it for its other tests (pyproject's --dist loadgroup)
@pytest.fixture(scope="module", params=[pytest.param("findings", marks=pytest.mark.xdist_group("report_findings")),
                                        pytest.param("small", marks=pytest.mark.xdist_group("small_report"))])
def sweep(request, tmp_path_factory) -> Path:
    if request.param == "findings":
        return findings_report(tmp_path_factory)
    return small_report(tmp_path_factory).parent


@lru_cache(maxsize=None)
def _stored(root: Path, source: str):
    path = root / source
    assert path.resolve().is_relative_to(root.resolve()), source
    return json.loads(path.read_text()) if source.endswith(".json") else pd.read_parquet(path)


def _value(root: Path, source: str, row: int, column: str):
    stored = _stored(root, source)
    if source == "controls.json":
        return stored["scores"][row][column]
    if source.endswith(".json"):
        return stored[column]
    return stored[column].iloc[row]


def _attributes(text: str) -> dict[str, str]:
    return {k: html.unescape(v) for k, v in re.findall(r"data-([\w-]+)='([^']*)'", text)}


def _text(fragment: str) -> str:
    return html.unescape(re.sub(r"<[^>]+>", "", fragment))


def _marked(page: str) -> list[tuple[dict, str]]:
    found = []
    for _, attrs, inner in _MARKED.findall(page):
        found.append((_attributes(attrs), _text(inner)))
    return found


@pytest.mark.slow
def test_every_marked_number_is_the_stored_value(sweep):
    page = (sweep / "index.html").read_text()
    marked = _marked(page)
    assert len(marked) >= 100
    sources = {a["source"] for a, _ in marked}
    assert {"summaries/specs.parquet", "summaries/references.parquet", "summaries/findings.parquet",
            "controls.json"} <= sources
    for attrs, shown in marked:
        value = _value(sweep, attrs["source"], int(attrs["row"]), attrs["column"])
        spec = attrs.get("fmt", "")
        expected = format_value(value, spec) if spec else fmt(value)
        assert shown == expected, (attrs, shown, value)


def _names(root: Path) -> list[str]:
    """Names the page prints that may hold digits: groups, scenes, labels, specs, references,
    and the registered metrics' titles and one-line definitions (the sweep's metrics.json)."""
    results = pd.read_parquet(root / "results.parquet")
    metrics = json.loads((root / "metrics.json").read_text())
    names = {text for entry in metrics.values() for text in (entry["title"], entry["summary"])}
    for column in ("group", "scene", "label", "label_plain", "label_unfiltered", "spec", "reference",
                   "reference_label"):
        if column in results:
            names |= set(results[column].dropna().astype(str))
    speed = root / "summaries" / "speed.parquet"
    if speed.is_file():
        frame = pd.read_parquet(speed)
        for column in ("scene", "label", "spec"):
            if column in frame:
                names |= set(frame[column].dropna().astype(str))
    return sorted(names, key=len, reverse=True)  # longest first: a name inside another goes with it


def _unmarked_digits(fragment: str, names: list[str]) -> str:
    text = _text(_MARKED.sub("", fragment))
    for word in (*names, *FIXED_WORDS):
        text = text.replace(word, " ")
    return " ".join(w for w in text.split() if re.search(r"\d", w))


def test_no_table_cell_shows_a_number_that_is_not_stored(sweep):
    page = (sweep / "index.html").read_text()
    cells = re.findall(r"<td([^>]*)>(.*?)</td>", page, re.S)
    assert len(cells) >= 100
    loose = [inner for attrs, inner in cells if "data-source=" not in attrs and re.search(r"\d", _text(inner))]
    unmarked = [(inner, _unmarked_digits(inner, [])) for inner in loose]
    assert [u for u in unmarked if u[1]] == []


def test_no_caption_or_reference_shows_a_number_that_is_not_stored(sweep):
    page = (sweep / "index.html").read_text()
    names = _names(sweep)
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", page, re.S)
    references = re.findall(r"<p class='ref'>(.*?)</p>", page, re.S)
    assert len(captions) >= 10 and references
    left = [(c[:80], _unmarked_digits(c, names)) for c in captions + references]
    assert [x for x in left if x[1]] == []


@pytest.mark.slow
@pytest.mark.xdist_group("small_report")
def test_a_number_changed_in_a_stored_table_changes_on_the_page(tmp_path_factory, tmp_path):
    """The page draws the stored summary, not a value of its own: edit one stored count and
    the page shows the edited value where it showed the old one (on the small sweep: a
    report of the larger one takes 5 s)."""
    import shutil

    from aaeval.report import write_report

    copy = tmp_path / "copy"
    shutil.copytree(small_report(tmp_path_factory).parent, copy, ignore=shutil.ignore_patterns("index.html", "figures", "tables", "viewer"))
    specs_path = copy / "summaries" / "specs.parquet"
    specs = pd.read_parquet(specs_path)
    specs.loc[0, "cells"] = 4242
    specs.to_parquet(specs_path, index=False)
    write_report(copy, formats=("png",))  # only the page is read
    page = (copy / "index.html").read_text()
    assert "data-source='summaries/specs.parquet' data-row='0' data-column='cells'>4242<" in page
