"""Hostile sweep folders for ``aaeval report``: a report output replaced
by a link to a file elsewhere is replaced, never written through; markup planted in the
records reaches the page escaped."""

from __future__ import annotations

import os

import pytest

from aaeval.cli import main
from aaeval.sweeps.store import SweepStore
from aaeval.sweeps.report_files import write_sweep_files
from tests.helpers.links_util import TINY, plant_markup, snapshot, sweep

@pytest.mark.slow
def test_a_report_output_replaced_by_a_link_is_replaced_not_written_through(world, capsys):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    # a draft names every output; each figure's SVG and PDF twins sit beside its PNG
    assert main(["report", str(out), "--quiet", "--png-only"]) == 0
    drafted = [p for d in ("figures", "tables", "viewer") for p in (out / d).iterdir()] + [out / "index.html"]
    twins = [p.with_suffix(s) for p in drafted if p.parent.name == "figures" for s in (".svg", ".pdf")]
    outputs = drafted + twins
    assert any(p.suffix == ".svg" for p in outputs)
    for p in outputs:
        p.unlink(missing_ok=True)
        os.symlink(outside / "victim.txt", p)
    before = snapshot(outside)
    assert main(["report", str(out), "--quiet"]) == 0, capsys.readouterr().err
    assert snapshot(outside) == before
    for p in outputs:
        assert p.is_file() and not p.is_symlink(), p
    # and a link sat at every output the full report writes
    written = {p for d in ("figures", "tables", "viewer") for p in (out / d).iterdir()} | {out / "index.html"}
    assert written == set(outputs)


@pytest.mark.slow
def test_markup_in_every_record_field_reaches_the_page_escaped(world, capsys):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    plant_markup(out)
    write_sweep_files(SweepStore(out))  # the tables the report reads are the sweep's: written again from the cells
    assert main(["report", str(out), "--quiet"]) == 0, capsys.readouterr().err
    page = (out / "index.html").read_text()
    assert "alert(" not in page.replace("alert(&#x27;x&#x27;)", "")
    # (a reference's kind is shown as the truth rule reads it, exact or seeded, not as stored text)
    for f in ("error", "host", "experiment", "group"):
        assert f"&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt;{f}" in page, f


def test_a_fail_above_that_is_not_finite_is_refused(tmp_path, capsys):
    from tests.helpers.cli_util import refused
    from tests.helpers.sweep_util import write_config

    for value in ("nan", "inf"):
        config = write_config(tmp_path, TINY.replace('metrics = ["rmse"]', f'metrics = ["rmse"]\nfail_above = {value}'))
        refused(["sweep", str(config), "--out", str(tmp_path / "o"), "--dry-run", "--quiet"], capsys, "fail_above")


def test_a_toml_array_nested_2000_deep_is_refused(tmp_path, capsys):
    from tests.helpers.cli_util import refused

    config = tmp_path / "deep.toml"
    config.write_text("a = " + "[" * 2000 + "]" * 2000 + "\n")
    refused(["sweep", str(config), "--out", str(tmp_path / "o"), "--dry-run", "--quiet"], capsys, "too deeply")


def test_a_billion_repeats_is_refused(tmp_path, capsys):
    from tests.helpers.cli_util import refused
    from tests.helpers.sweep_util import write_config

    for value in ("1e9", "1000000000"):
        config = write_config(tmp_path, TINY.replace('metrics = ["rmse"]', f'metrics = ["rmse"]\nrepeats = {value}'))
        refused(["sweep", str(config), "--out", str(tmp_path / "o"), "--dry-run", "--quiet"], capsys, "repeats")
