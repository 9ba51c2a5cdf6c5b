"""Studies behind the same boundary as sweeps and reports: links refused, inputs bounded,
every study.toml field checked against the config before the sweep runs, generated text
escaped so the README the tool writes is one it accepts again."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from aaeval.cli import main
from aaeval.studies.folder import StudyError
from aaeval.studies.readme import BEGIN, END
from aaeval.studies.run import run_study
from aaeval.studies.study import load_study
from tests.helpers.cli_util import refused

ROOT = Path(__file__).resolve().parents[2]
INTERPENETRATING = ROOT / "configs" / "scenes" / "interpenetrating.toml"

CONFIG = """
[experiment]
name = "boundary"
reference = "catmull"
metrics = ["rmse"]
temporal = ["sum_variation"]

[[groups]]
name = "fence"
scenes = [{generator = "picket", difficulty = [1.0], bars = 2, width = 4, height = 4, frames = 2}]
methods = ["point", "catmull"]
"""
STUDY = """
[study]
paper = "E. Catmull, test"
seed = "000_test.txt"

[[summaries]]
kind = "sums"
group = "fence"
steady = ["catmull"]

[[summaries]]
kind = "pixel"
group = "fence"
pixel = [1, 2]

[[summaries]]
kind = "hidden_lines"
scenes = ["SCENE"]
"""


def _study(tmp_path: Path, study: str = STUDY, config: str = CONFIG) -> Path:
    folder = tmp_path / "study"
    folder.mkdir()
    (folder / "config.toml").write_text(config)
    (folder / "study.toml").write_text(study.replace("SCENE", str(INTERPENETRATING)))
    (folder / "README.md").write_text(f"# Test\n\n{BEGIN}\nold\n{END}\n")
    return folder


def _study_refused(tmp_path, capsys, folder: Path, message: str) -> None:
    """``aaeval study`` refuses in one line naming the rule, before the sweep (no results)
    and with the README untouched."""
    before = (folder / "README.md").read_bytes()
    refused(["study", folder, "-j", "1", "-q", "--cache", tmp_path / "cache"], capsys, message,
            written=[folder / "results"])
    assert (folder / "README.md").read_bytes() == before


@pytest.mark.parametrize("edit, message", [
    (lambda s: s.replace('group = "fence"\nsteady', 'group = "nowhere"\nsteady'), "is not a group of the config"),
    (lambda s: s.replace('steady = ["catmull"]', 'steady = "catmull"'), "steady: expected a list of 1 to 64 names"),
    (lambda s: s.replace('steady = ["catmull"]', 'steady = ["catmull"]\ntolerance = "small"'), "tolerance"),
    (lambda s: s.replace('kind = "sums"', 'kind = ["sums"]'), "is not a summary kind"),
    (lambda s: s.replace('pixel = [1, 2]', 'pixel = [true, true]'), "pixel: expected [row, column]"),
    (lambda s: s.replace('pixel = [1, 2]', 'pixel = [1, 99]'), "outside the 4x4 image"),
    (lambda s: s.replace('pixel = [1, 2]', 'pixel = [1, 2]\nframe = 5'), "frame 5 is not among"),
    (lambda s: s.replace('pixel = [1, 2]', 'pixel = [1, 2]\nagree = ["nearest"]'), "not a method of the group"),
    (lambda s: s.replace('pixel = [1, 2]', 'pixel = [1, 2]\ntitle = 3'), "title: expected a string"),
    (lambda s: s + '\n[[summaries]]\nkind = "temporal"\ngroup = "fence"\nmetrics = ["flicker"]\n',
     "'flicker' is not measured by the group"),
    (lambda s: s + '\n[[summaries]]\nkind = "errors"\ngroup = "fence"\nmetrics = ["edge_rmse"]\n',
     "'edge_rmse' is not measured by the group"),
    (lambda s: s + '\n[[summaries]]\nkind = "pairs"\ngroup = "fence"\npairs = [["point"]]\n', "pairs: expected two"),
    (lambda s: s.replace('scenes = ["SCENE"]', 'scenes = ["missing.toml"]'), "scenes:"),
    (lambda s: s.replace('scenes = ["SCENE"]', 'scenes = ["SCENE", "SCENE"]'), "share a file name"),
    (lambda s: s.replace('seed = "000_test.txt"', 'seed = "000_test.txt"\nconfig = 7'), "[study].config"),
    (lambda s: s.replace('seed = "000_test.txt"', 'seed = "000_test.txt"\nresults = "../../elsewhere"'),
     "[study].results must be a folder inside the study folder"),
    (lambda s: s.replace('kind = "sums"', 'kind = "averages"'), "not a summary kind"),
    (lambda s: s.replace('steady = ["catmull"]', 'steady = ' + repr(["catmull"] * 100)),
     "steady: expected a list of 1 to 64 names"),
    (lambda s: s.replace('steady = ["catmull"]', 'steady = ["catmull"]\ncolour = "red"'), "unknown key"),
    (lambda s: s.replace('paper = "E. Catmull, test"\n', ""), "paper"),
    (lambda s: s + '\n[[summaries]]\nkind = "figure"\nfigure = "nowhere"\n', "is not a study figure"),
    (lambda s: s + '\n[[summaries]]\nkind = "temporal"\ngroup = "fence"\nmetrics = ["sum_variation"]\n'
               'ratio_above = 2.0\n', "give ratio = [method, method]"),
])
def test_every_field_is_checked_before_the_sweep(tmp_path, capsys, edit, message):
    folder = _study(tmp_path, edit(STUDY))
    _study_refused(tmp_path, capsys, folder, message)


def test_within_noise_of_a_truth_without_one_is_refused_before_the_sweep(tmp_path, capsys):
    config = CONFIG.replace('reference = "catmull"', 'reference = "supersample:k=4"')
    study = STUDY + '\n[[summaries]]\nkind = "errors"\ngroup = "fence"\nwithin_noise = ["catmull"]\n'
    _study_refused(tmp_path, capsys, _study(tmp_path, study, config), "own error is unknown")


def test_a_drawing_folder_that_is_a_link_is_refused(tmp_path, capsys):
    folder = _study(tmp_path)
    outside = tmp_path / "outside"
    outside.mkdir()
    (folder / "hidden-lines").symlink_to(outside)
    _study_refused(tmp_path, capsys, folder, "is a symbolic link")
    assert list(outside.iterdir()) == []


def test_a_readme_that_is_a_link_is_refused(tmp_path, capsys):
    folder = _study(tmp_path)
    target = tmp_path / "elsewhere.md"
    target.write_text(f"{BEGIN}\n{END}\n")
    (folder / "README.md").unlink()
    (folder / "README.md").symlink_to(target)
    assert main(["study", str(folder), "-j", "1", "-q"]) == 2
    assert "is a symbolic link" in capsys.readouterr().err
    assert target.read_text() == f"{BEGIN}\n{END}\n"


def test_a_huge_readme_is_refused_unread(tmp_path, capsys):
    folder = _study(tmp_path)
    with open(folder / "README.md", "r+b") as f:  # sparse: 3 GiB claimed, nothing on disk
        f.truncate(3 << 30)
    assert main(["study", str(folder), "--no-run"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "README" in err
    os.truncate(folder / "README.md", 0)


def test_generated_text_is_escaped_and_the_readme_is_accepted_again(tmp_path):
    hostile = f"Sums {END} <script>alert(1)</script> | a | b"
    study = STUDY.replace('steady = ["catmull"]', f'steady = ["catmull"]\ntitle = """{hostile}"""\n'
                          'note = "line one\\n\\n### not a heading <img src=x>"')
    folder = _study(tmp_path, study)
    run_study(load_study(folder), workers=1, cache_dir=tmp_path / "cache")
    text = (folder / "README.md").read_text()
    assert text.count(END) == 1 and text.count(BEGIN) == 1
    assert "<script>" not in text and "<img" not in text
    assert "&lt;script&gt;" in text
    heading = next(line for line in text.splitlines() if line.startswith("### Sums"))
    assert "|" not in heading  # a bar would split a table row; the title stays one heading line
    assert "\n### not a heading" not in text
    load_study(folder)  # the README it wrote is one it accepts
    run_study(load_study(folder), run=False)


def test_a_sum_constant_at_zero_does_not_vary(tmp_path):
    scene = tmp_path / "black.toml"
    scene.write_text('[image]\nwidth = 4\nheight = 2\nbackground = [0.0, 0.0, 0.0]\n\n[[polygons]]\n'
                     'color = [0.0, 0.0, 0.0]\nvertices = [[0.5, 0.5, 1.0], [2.5, 0.5, 1.0], [1.5, 1.5, 1.0]]\n')
    config = CONFIG.replace('scenes = [{generator = "picket", difficulty = [1.0], bars = 2, width = 4, height = 4, '
                            'frames = 2}]', f'scenes = ["{scene}"]\nanimate = {{ frames = 3, translate = [0.1, 0.0] }}')
    folder = _study(tmp_path, STUDY.replace("pixel = [1, 2]", "pixel = [1, 1]"), config)
    run_study(load_study(folder), workers=1, cache_dir=tmp_path / "cache")
    text = (folder / "README.md").read_text()
    assert "inf" not in text
    assert "(relative variation 0.0e+00)" in text


def test_a_study_folder_that_is_a_link_is_refused(tmp_path):
    folder = _study(tmp_path)
    link = tmp_path / "linked"
    link.symlink_to(folder)
    with pytest.raises(StudyError, match="not a study folder"):
        load_study(link)
