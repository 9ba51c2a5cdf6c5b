"""The studies in experiments/ and the tool that writes their README's measured part
(``aaeval study``, :mod:`aaeval.studies`)."""

from __future__ import annotations

import re
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore, load_experiment, plan
from aaeval.studies.folder import StudyError
from aaeval.studies.readme import BEGIN, END, replace_section
from aaeval.studies.run import run_study
from aaeval.studies.study import load_study

ROOT = Path(__file__).resolve().parents[2]
STUDIES = sorted(p.parent for p in (ROOT / "experiments").glob("*/study.toml"))
#: Each shipped study's paper: a word its README and study.toml must name (the surname).
PAPERS = {"catmull1978": "Catmull", "khan-figures": "Khan", "amanatides1992": "Amanatides",
          "weiler-atherton1977": "Weiler"}


def test_there_are_the_four_studies():
    # At least four, one per seed paper, each listed in the index
    assert {p.name for p in STUDIES} >= set(PAPERS)
    index = (ROOT / "experiments" / "README.md").read_text()
    for folder in STUDIES:
        assert f"({folder.name}/README.md)" in index, f"experiments/README.md does not link {folder.name}"


@pytest.mark.parametrize("folder", STUDIES, ids=lambda p: p.name)
def test_study_config_parses_and_readme_names_its_paper(folder):
    study = load_study(folder)
    experiment = load_experiment(study.config)
    assert plan(experiment), "a dry run plans no cell"
    text = study.readme.read_text()
    surname = PAPERS.get(folder.name, study.paper.split()[1])
    assert surname in study.paper and surname in text
    assert study.seed in text, f"{study.readme} does not name its seed file {study.seed}"
    head, generated = text.split(BEGIN)[0], text.split(BEGIN)[1].split(END)[0]
    assert "## The claim" in head and "## What was measured" in head
    # committed with the section generated from a real run: the date and machine are in it
    assert re.search(r"Generated \d{4}-\d\d-\d\d \d\d:\d\d UTC by `aaeval study", generated)
    assert "Machine:" in generated


@pytest.mark.parametrize("folder", STUDIES[:1], ids=lambda p: p.name)
def test_sweep_dry_run_accepts_a_study_config(folder, tmp_path, capsys):
    # the config is an ordinary sweep config: scene paths resolve relative to it, from any cwd
    assert main(["sweep", str(folder / "config.toml"), "--out", str(tmp_path / "out"), "--dry-run"]) == 0
    assert "0 done" in capsys.readouterr().out


# --- the generator on a tiny sweep ---------------------------------------------------------

CONFIG = """
[experiment]
name = "tiny-study"
reference = "catmull"
metrics = ["rmse"]
temporal = ["sum_variation", "flicker"]

[[groups]]
name = "fence"
scenes = [{generator = "picket", difficulty = [1.0], bars = 4, width = 8, height = 4, frames = 4}]
methods = ["point", "catmull", "weiler-atherton"]
"""
STUDY = """
[study]
paper = "E. Catmull, test"
seed = "000_test.txt"

[[summaries]]
kind = "sums"
group = "fence"
steady = ["catmull", "weiler-atherton"]
unsteady = ["point"]

[[summaries]]
kind = "temporal"
group = "fence"
metrics = ["sum_variation", "flicker"]
ratio = ["point", "catmull"]

[[summaries]]
kind = "errors"
group = "fence"

[[summaries]]
kind = "pairs"
group = "fence"
pairs = [["weiler-atherton", "catmull"]]
below = 0.0   # never holds (no difference is below 0): a failed expectation is reported

[[summaries]]
kind = "pixel"
group = "fence"
pixel = [1, 2]

[[summaries]]
kind = "hidden_lines"
scenes = ["SCENE"]
"""
INTERPENETRATING = ROOT / "configs" / "scenes" / "interpenetrating.toml"
HEAD = "# Tiny study\n\nHand-written: the claim.\n\n## What was measured\n\n"
TAIL = "\n\nHand-written text after the section stays.\n"


def _tiny(tmp_path: Path) -> Path:
    folder = tmp_path / "tiny"
    folder.mkdir()
    (folder / "config.toml").write_text(CONFIG)
    (folder / "study.toml").write_text(STUDY.replace("SCENE", str(INTERPENETRATING)))
    (folder / "README.md").write_text(f"{HEAD}{BEGIN}\nold text\n{END}{TAIL}")
    return folder


def _row(text: str, first: str) -> list[str]:
    """The cells of the markdown table row whose first cell is ``first``."""
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] == first:
            return cells
    raise AssertionError(f"no row {first!r}")


def test_generated_section_replaced_from_the_store(tmp_path):
    folder = _tiny(tmp_path)
    study = load_study(folder)
    when = datetime(2026, 1, 2, 3, 4, tzinfo=timezone.utc)
    run_study(study, workers=1, cache_dir=tmp_path / "cache", now=when)
    text = (folder / "README.md").read_text()
    # only the part between the markers changed
    assert text.startswith(HEAD + BEGIN) and text.endswith(END + TAIL)
    assert "old text" not in text
    assert "Generated 2026-01-02 03:04 UTC" in text
    # expectations: the sums' holds, the impossible bound on the pair does not, and the count says so
    assert "`catmull`, `weiler-atherton` within 1e-09 of the reference's sum in every frame, `point` not. **Holds**" in text
    assert "every difference below 0. **Does not hold**" in text
    assert "1 of 2 hold" in text
    from aaeval.api import open_sweep

    sweep = open_sweep(folder / "results")
    r = sweep.results
    point = r[r["label"] == "point"]["intensity_sum"]
    # sums: the table's numbers are the store's
    sums = _row(text, "`point`")
    assert float(sums[2]) == pytest.approx(point.min(), rel=1e-3)
    assert float(sums[3]) == pytest.approx(point.max(), rel=1e-3)
    assert float(sums[4]) == pytest.approx(point.mean(), rel=1e-3)
    # temporal: the store's temporal.parquet
    t = sweep.temporal.set_index("label")
    temporal = _row(text, "`picket@1`")  # first temporal row: point
    assert temporal[1] == "`point`"
    assert float(temporal[3]) == pytest.approx(t.loc["point", "sum_variation"], rel=1e-3)
    assert float(temporal[4]) == pytest.approx(t.loc["point", "flicker"], rel=1e-3)
    # pairs: recomputed here from the stored images
    store = SweepStore(folder / "results")
    wa = r[r["label"] == "weiler-atherton"].set_index("frame")["key"]
    cm = r[r["label"] == "catmull"].set_index("frame")["key"]
    diff = max(float(np.max(np.abs(store.load_image(wa[k]) - store.load_image(cm[k])))) for k in wa.index)
    pair = _row(text, "`weiler-atherton` vs `catmull`")
    assert float(pair[3]) == pytest.approx(diff, rel=1e-3, abs=1e-300)
    # pixel: the stored reference's value at (row 1, column 2) of frame 0
    pixel = _row(text, "`catmull` (reference)")
    reference = store.load_reference(r[r["frame"] == 0]["reference_key"].iloc[0])
    assert [float(v) for v in pixel[1:4]] == pytest.approx(list(reference[1, 2]), abs=1e-4)
    # hidden lines: the drawing is written beside the README, its segments counted
    from aaeval.scenes import load_scene
    from aaeval.weiler_atherton.lines import visible_edges

    svg = (folder / "hidden-lines" / "interpenetrating.svg").read_text()
    lines = _row(text, "[`interpenetrating`](hidden-lines/interpenetrating.svg)")
    assert int(lines[2]) == svg.count("<line ") == len(visible_edges(load_scene(INTERPENETRATING)))
    # regenerating from the same results (no run) with the same date changes nothing
    before = text
    run_study(load_study(folder), run=False, now=when)
    assert (folder / "README.md").read_text() == before


def test_cli_regenerates_without_running(tmp_path, capsys):
    folder = _tiny(tmp_path)
    assert main(["study", str(folder), "--no-run"]) == 2  # nothing run yet: one line, exit 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no results.parquet" in err
    assert main(["study", str(folder), "-j", "1", "-q", "--cache", str(tmp_path / "cache")]) == 0
    assert "Generated " in (folder / "README.md").read_text()
    # a config edited since the sweep: its README is not rewritten from the old results
    (folder / "config.toml").write_text(CONFIG.replace('name = "tiny-study"', 'name = "tiny-study-2"'))
    before = (folder / "README.md").read_text()
    assert main(["study", str(folder), "--no-run"]) == 2
    assert "another version" in capsys.readouterr().err
    assert (folder / "README.md").read_text() == before


@pytest.mark.parametrize("readme, message", [
    ("no markers at all\n", "markers"),
    (f"{END}\n{BEGIN}\n", "markers"),
    (f"{BEGIN}\n{BEGIN}\n{END}\n", "markers"),
])
def test_readme_without_its_markers_is_refused(tmp_path, readme, message):
    folder = _tiny(tmp_path)
    (folder / "README.md").write_text(readme)
    with pytest.raises(StudyError, match=message):
        load_study(folder)


def test_missing_folder_is_one_line(tmp_path, capsys):
    assert main(["study", str(tmp_path / "nowhere")]) == 2
    assert "not a study folder" in capsys.readouterr().err


def test_replace_section_keeps_the_rest():
    text = f"a\n{BEGIN}\nx\n{END}\nb\n"
    assert replace_section(text, "new") == f"a\n{BEGIN}\n\nnew\n\n{END}\nb\n"


def test_errors_against_a_seeded_truth_print_its_noise(tmp_path):
    # Mitsuba on 3 x 3 pixels (about 1 s): the error table divides each error by the truth's noise
    folder = tmp_path / "seeded"
    folder.mkdir()
    fig1 = ROOT / "configs" / "scenes" / "catmull_fig1.toml"
    (folder / "config.toml").write_text(f"""
[experiment]
name = "seeded"
reference = "mitsuba:spp=64,seed=0"
metrics = ["rmse"]

[[groups]]
name = "fig1"
scenes = ["{fig1}"]
methods = ["point", "catmull"]
""")
    (folder / "study.toml").write_text('[study]\npaper = "E. Catmull"\nseed = "x.txt"\n\n'
                                       '[[summaries]]\nkind = "errors"\ngroup = "fig1"\n')
    (folder / "README.md").write_text(f"{BEGIN}\n{END}\n")
    run_study(load_study(folder), workers=1, cache_dir=tmp_path / "cache")
    text = (folder / "README.md").read_text()
    from aaeval.api import open_sweep

    r = open_sweep(folder / "results").results.set_index("label")
    row = _row(text, "`catmull_fig1`")  # the first row: point
    assert row[1] == "`point`"
    noise = float(r.loc["point", "reference_noise_rmse"])
    assert noise > 0
    assert float(row[2]) == pytest.approx(r.loc["point", "rmse"], rel=1e-3)
    assert float(row[5]) == pytest.approx(r.loc["point", "rmse"] / noise, rel=1e-2)
    assert "within 1.5x the truth's noise" in text
