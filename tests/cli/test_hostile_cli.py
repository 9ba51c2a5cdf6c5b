"""Hostile command lines: frame counts of scene files budgeted as generators'
are (case 7); an output folder that cannot be written is refused before any rendering,
naming the user's path (case 10); malformed import options are refused naming the option
(case 12)."""

from __future__ import annotations

from pathlib import Path

import pytest

from aaeval.cli import main

from tests.helpers.cli_util import refused

ANIMATED = """[image]
width = 16
height = 16
background = [0.0, 0.0, 0.0]

[animation]
frames = {frames}
translate = [0.0, 0.0]

[[polygons]]
color = [1.0, 0.5, 0.0]
vertices = [[1.3, 1.2, 0.0], [14.7, 2.1, 0.0], [3.1, 14.9, 0.0]]
"""

CONFIG = """[experiment]
name = "frames"
reference = "point"
metrics = ["rmse"]

[[groups]]
name = "g"
scenes = ["scene.toml"]
methods = ["point"]
frames = "all"
"""


# --- case 7 --------------------------------------------------------------------------------

@pytest.fixture
def billion_frames(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "scene.toml"
    scene.write_text(ANIMATED.format(frames=1_000_000_000))
    return scene


def test_compare_all_frames_of_a_billion_frame_file_is_refused(billion_frames, capsys):
    refused(["compare", str(billion_frames), "-m", "point", "-r", "supersample:k=2", "--frames", "all",
             "--json", "c.json", "--quiet"], capsys, billion_frames, "frames")
    refused(["compare", str(billion_frames), "-m", "point", "-r", "supersample:k=2", "--frames", "999999999",
             "--quiet"], capsys, billion_frames, "frames")
    assert not Path("c.json").exists()


def test_invariance_of_a_billion_frame_file_is_refused(billion_frames, capsys):
    refused(["invariance", str(billion_frames), "-m", "point"], capsys, billion_frames, "frames")


def test_sweep_of_all_frames_of_a_billion_frame_file_is_refused(billion_frames, capsys, tmp_path):
    (tmp_path / "exp.toml").write_text(CONFIG)
    refused(["sweep", str(tmp_path / "exp.toml"), "--out", str(tmp_path / "out"), "--dry-run"], capsys,
            billion_frames, "frames")
    assert not (tmp_path / "out").exists()


def test_a_million_frames_of_a_deep_stack_are_refused_for_their_time(tmp_path, capsys, monkeypatch):
    """Within the pixel budget (25 x 1 x 1e6 frames) but each frame a render: invariance and
    compare estimate the whole run's time before the first frame (found by the fuzz run)."""
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "scene.toml"
    square = "[[polygons]]\ncolor = [0.5, 0.5, 0.5]\nvertices = [[4, 4, 1.0], [40, 5, 1], [39, 40, 1], [3, 41, 1]]\n"
    scene.write_text("[image]\nwidth = 25\nheight = 1\n\n[animation]\nframes = 1000000\ntranslate = [0.0, 0.0]\n\n"
                     + square * 60)
    refused(["invariance", str(scene), "-m", "catmull", "--quiet"], capsys, scene, "AAEVAL_MAX_SECONDS")
    refused(["compare", str(scene), "-m", "point", "-r", "catmull", "--frames", "all", "--quiet"], capsys, scene,
            "AAEVAL_MAX_SECONDS")


def test_an_animation_within_the_budget_still_runs(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "scene.toml"
    scene.write_text(ANIMATED.format(frames=3))
    assert main(["invariance", str(scene), "-m", "point", "--quiet"]) == 0
    assert "frames 3" in capsys.readouterr().out


# --- case 10 -------------------------------------------------------------------------------
# /proc takes no new files, even for root (a chmod-ed folder does not stop root)

def test_compare_json_into_an_unwritable_folder_fails_before_rendering(tmp_path, capsys, monkeypatch):
    import aaeval.sweeps.compare as compare

    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "scene.toml"
    scene.write_text(ANIMATED.format(frames=1))
    rendered = []
    monkeypatch.setattr(compare, "run_comparison", lambda *a, **k: rendered.append(1) or {})
    err = refused(["compare", str(scene), "-m", "point", "-r", "supersample:k=2", "--json", "/proc/c.json",
                   "--quiet"], capsys, "/proc/c.json")
    assert not rendered
    assert "/proc/." not in err  # the user's path, not a temporary file beside it


def test_import_into_an_unwritable_folder_names_the_users_path(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = refused(["import", "text", "abc", "-o", "/proc/x.toml"], capsys, "/proc/x.toml")
    assert "/proc/." not in err


def test_report_into_an_unwritable_folder_fails_before_any_work(tmp_path, capsys, monkeypatch):
    import tempfile

    import aaeval.report as report

    folder = tmp_path / "sweep"
    folder.mkdir()
    real = tempfile.TemporaryFile

    def read_only(*args, dir=None, **kwargs):  # the folder behaves as on a read-only file system
        if dir is not None and Path(dir) == folder:
            raise OSError(30, "Read-only file system", str(folder / ".aaeval-probe-x"))
        return real(*args, dir=dir, **kwargs)

    monkeypatch.setattr(tempfile, "TemporaryFile", read_only)
    called = []
    monkeypatch.setattr(report, "write_report", lambda *a, **k: called.append(1))
    err = refused(["report", str(folder), "--quiet"], capsys, folder, "Read-only file system")
    assert not called and ".aaeval-probe" not in err


# --- case 12 -------------------------------------------------------------------------------

@pytest.mark.parametrize("argv, option", [
    (["--margin", "nan"], "--margin"),
    (["--margin=-1e9"], "--margin"),
    (["--margin", "1e12"], "--margin"),
    (["--origin", "nan", "3"], "--origin"),
    (["--origin", "1e300", "3"], "--origin"),
    (["--color", "nan", "0", "0"], "--color"),
    (["--color", "2", "0", "0"], "--color"),
    (["--background", "0", "inf", "0"], "--background"),
    (["--size", "nan"], "--size"),
    (["--translate", "nan", "0"], "--translate"),
])
def test_import_text_options_are_refused_naming_the_option(tmp_path, capsys, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    err = refused(["import", "text", "abc", *argv, "-o", "t.toml"], capsys, option)
    assert "t.toml" not in err  # the option is at fault, not the output file
    assert not (tmp_path / "t.toml").exists()


@pytest.mark.parametrize("argv, option", [
    (["--scale", "nan"], "--scale"),
    (["--scale", "-2"], "--scale"),
    (["--background", "nan", "0", "0"], "--background"),
])
def test_import_svg_options_are_refused_naming_the_option(tmp_path, capsys, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4">'
                                    '<rect width="2" height="2"/></svg>')
    refused(["import", "svg", "a.svg", *argv, "-o", "t.toml"], capsys, option)
    assert not (tmp_path / "t.toml").exists()
