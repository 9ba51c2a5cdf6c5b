"""Findings answer from every group that measured a question, each table naming the truth it
was judged against (seeded with its noise, or exact), and the lead states no single truth."""

from __future__ import annotations

import re

import pandas as pd
import pytest

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.report import write_report

pytestmark = pytest.mark.xdist_group("findings_every_group")

CONFIG = """
[experiment]
name = "two-groups"
reference = "catmull"
metrics = ["rmse", "edge_rmse"]
temporal = ["flicker"]

[[groups]]
name = "bars-exact"
reference = "catmull"
scenes = [{generator = "edges", difficulty = [0.1], size = 10, frames = 2}]
methods = ["point", "catmull", "supersample"]
options.supersample = { k = [4] }

[[groups]]
name = "fan-seeded"
reference = "mitsuba:spp=16,seed=0"
scenes = [{generator = "fan", difficulty = [6], size = 10}]
methods = ["point", "abuffer"]
"""


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("two-groups")
    (tmp / "exp.toml").write_text(CONFIG)
    out = tmp / "sweep"
    run_sweep(load_experiment(tmp / "exp.toml"), out, workers=1, quiet=True, cache_dir=tmp / "cache")
    write_report(out, formats=("png",))
    return out, (out / "index.html").read_text()


def _question(text: str, key: str) -> str:
    findings = text[text.index("<h2 id='findings'>"):text.index("<h2 id='how-to-read'>")]
    return findings.split(f"<h3 id='finding-{key}'>")[1].split("<h3 ")[0]


@pytest.mark.slow
def test_two_groups_measuring_edge_aliasing_show_both_rankings(page):
    out, text = page
    edges = _question(text, "edges")
    # each group's leader sentence and its own table, in the order the groups answer
    assert "group bars-exact)" in edges and "group fan-seeded)" in edges
    tables = re.findall(r"<table class='findings' data-group='([^']+)'>", edges)
    assert tables == ["bars-exact", "fan-seeded"]
    found = pd.read_parquet(out / "summaries" / "findings.parquet")
    mine = found[found["question"] == "edges"]
    for group, methods in (("bars-exact", {"point", "catmull", "supersample:k=4"}), ("fan-seeded", {"point", "abuffer"})):
        block = edges.split(f"<table class='findings' data-group='{group}'>")[1].split("</table>")[0]
        labels = re.findall(r"<td data-source[^>]*data-column='label'[^>]*>([^<]+)</td>", block)
        rows = mine[mine["group"] == group].sort_values("rank")
        assert labels == list(rows["label"]), group
        assert {m.split(":")[0] for m in labels} == {m.split(":")[0] for m in methods}
        # the ranking is the group's own: best (lowest edge RMSE) first
        assert list(rows["value"]) == sorted(rows["value"])


@pytest.mark.slow
def test_each_findings_table_names_its_truth(page):
    out, text = page
    edges = _question(text, "edges")
    truths = re.findall(r"<p class='dl truth'>Judged against <code>([^<]+)</code> \(([^)]+)\)", edges)
    assert len(truths) == 2
    (exact_ref, exact_words), (seeded_ref, seeded_words) = truths
    assert exact_ref == "catmull" and exact_words == "exact, no noise"
    assert seeded_ref.startswith("mitsuba") and seeded_words.startswith("seeded, noise RMS ")
    results = pd.read_parquet(out / "results.parquet")
    noise = results[results["group"] == "fan-seeded"].drop_duplicates(["scene", "frame"])["reference_noise_rmse"].mean()
    assert float(seeded_words.rsplit(" ", 1)[1]) == pytest.approx(noise, rel=1e-2)
    # every findings table of the page names its truth (the speed pass has none: this sweep has no speed pass)
    findings = text[text.index("<h2 id='findings'>"):text.index("<h2 id='how-to-read'>")]
    assert findings.count("<table class='findings'") == findings.count("<p class='dl truth'>")
    # the lead states no single truth for every group
    lead = findings.split("<h3 ")[0]
    assert "every method is judged against" not in lead.lower()
    assert "Each table names the truth it was judged against" in lead
