"""Every input error is one line naming the file or option and the rule, exit 2, no
traceback, nothing written; requests that cannot fit are refused before any work."""

from __future__ import annotations

import errno
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.cli_util import refused

ROOT = Path(__file__).resolve().parents[2]

SCENE = (Path(__file__).resolve().parents[1] / "data" / "scenes" / "triangle_three_frames.toml").read_text()


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    return path


# --- scene files ------------------------------------------------------------------


def test_a_binary_scene_file_is_named(tmp_path, capsys):
    bad = tmp_path / "image.toml"
    bad.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    refused(["render", bad, "-o", tmp_path / "x.npy"], capsys, bad, "UTF-8", written=[tmp_path / "x.npy"])


@pytest.mark.parametrize("colour, rule", [("[1.5, 0, 0]", "[0, 1]"), ("[-0.1, 0, 0]", "[0, 1]"),
                                          ("[1e308, 0, 0]", "[0, 1]")])
def test_colours_outside_0_1_are_refused(tmp_path, capsys, colour, rule):
    bad = tmp_path / "c.toml"
    bad.write_text(SCENE.replace("color = [1.0, 0.5, 0.0]", f"color = {colour}"))
    refused(["render", bad, "-o", tmp_path / "x.npy"], capsys, bad, "polygons[0].color", rule)
    bg = tmp_path / "bg.toml"
    bg.write_text(SCENE.replace("height = 9", f"height = 9\nbackground = {colour}"))
    refused(["render", bg, "-o", tmp_path / "x.npy"], capsys, "[image].background", rule)


def test_an_animation_that_overflows_is_refused(tmp_path, capsys):
    bad = tmp_path / "far.toml"
    bad.write_text(SCENE.replace("translate = [0.25, 0.125]", "translate = [1.7e308, 0]"))
    refused(["render", bad, "-o", tmp_path / "x.npy"], capsys, bad, "[animation]", "frame 2")


def test_a_shaded_object_with_absurd_segments_is_refused_at_once(tmp_path, capsys):
    from aaeval.scenes.shaded import MAX_SEGMENTS

    import re

    content = (ROOT / "configs" / "scenes" / "shaded" / "cylinders.toml").read_text()

    bad = tmp_path / "many.toml"
    bad.write_text(re.sub(r"segments\s*=\s*\d+", "segments = 10000000", content, count=1))
    refused(["render", bad, "-o", tmp_path / "x.npy"], capsys, bad, "segments", str(MAX_SEGMENTS))


# --- method options and budgets -----------------------------------------------------


@pytest.mark.parametrize("spec, needle", [
    ("catmull:power=nan", "'power'"), ("catmull:power=inf", "'power'"), ("supersample:k=0", ">= 1"),
    ("supersample:k=2.5", "expected int"), ("jitter:seed=-1", ">= 0"),
])
def test_options_are_checked_by_name_type_and_range(scene, tmp_path, capsys, spec, needle):
    refused(["render", scene, "-m", spec, "-o", tmp_path / "x.npy"], capsys, needle, written=[tmp_path / "x.npy"])


def test_an_option_validator_and_maximum_are_enforced():
    from aaeval.options import Option, OptionError

    odd = Option(int, 1, "odd", maximum=9, check=lambda v: None if v % 2 else "must be odd")
    assert odd.convert("3", "opt") == 3
    with pytest.raises(OptionError, match="<= 9"):
        odd.convert("11", "opt")
    with pytest.raises(OptionError, match="must be odd"):
        odd.convert("4", "opt")


@pytest.mark.parametrize("spec", ["supersample:k=100000", "jitter:k=100000"])
def test_sampling_that_cannot_fit_is_refused_with_its_estimate(scene, tmp_path, capsys, spec):
    err = refused(["render", scene, "-m", spec, "-o", tmp_path / "x.npy"], capsys, "samples",
                   written=[tmp_path / "x.npy"])
    assert "AAEVAL_MAX_SAMPLES" in err or "memory" in err


def test_an_image_bigger_than_memory_is_refused_with_its_estimate(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "2G")  # this machine's size must not decide the test
    big = tmp_path / "big.toml"
    big.write_text(SCENE.replace("width = 12", "width = 16384").replace("height = 9", "height = 16384"))
    refused(["render", big, "-m", "catmull", "-o", tmp_path / "x.npy"], capsys, "GiB", "memory",
             written=[tmp_path / "x.npy"])


def test_an_enlargement_that_cannot_fit_is_refused_before_rendering(scene, tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "1G")
    out = tmp_path / "x.png"
    refused(["render", scene, "--scale", "5000", "-o", out], capsys, "--scale", "GiB", written=[out])


# --- outputs, checked before rendering ------------------------------------------------


def test_clashing_outputs_are_refused_before_rendering(scene, tmp_path, capsys):
    out = tmp_path / "a.npy"
    refused(["render", scene, "-o", out, "--stats", out], capsys, "-o", "--stats", out, written=[out])


def test_a_directory_as_output_is_refused_before_rendering(scene, tmp_path, capsys):
    (tmp_path / "d.npy").mkdir()
    refused(["render", scene, "-o", tmp_path / "d.npy"], capsys, "-o", "directory")
    (tmp_path / "s").mkdir()
    refused(["render", scene, "-o", tmp_path / "x.npy", "--stats", tmp_path / "s"], capsys, "--stats", "directory",
             written=[tmp_path / "x.npy"])


def test_an_unwritable_place_is_refused_before_rendering(scene, tmp_path, capsys):
    refused(["render", scene, "-o", "/proc/aaeval-test.npy"], capsys, "-o", "/proc")
    afile = tmp_path / "file"
    afile.write_text("x")
    refused(["render", scene, "-o", afile / "x.npy"], capsys, afile, "no such folder")
    refused(["render", scene, "--mkdir", "-o", afile / "x.npy"], capsys, "-o", "not a directory")
    refused(["hidden-lines", scene, "-o", "/proc/aaeval-test.svg"], capsys, "-o", "/proc")


def test_sweep_out_and_cache_must_be_writable_folders(tmp_path, capsys):
    from tests.helpers.sweep_util import write_config

    config = write_config(tmp_path)
    afile = tmp_path / "file"
    afile.write_text("x")
    refused(["sweep", config, "--out", afile], capsys, "--out", "not a directory")
    refused(["sweep", config, "--out", tmp_path / "o", "--cache", afile], capsys, "--cache", "not a directory")
    refused(["sweep", config, "--out", "/proc/aaeval-sweep"], capsys, "--out", "/proc")


def test_the_command_line_turns_os_errors_into_one_line(tmp_path, capsys, monkeypatch):
    def no_space(*a, **k):
        raise OSError(errno.ENOSPC, "no space left on device", str(tmp_path / "x.npy"))

    monkeypatch.setattr("aaeval.imageio.save_image", no_space)
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    refused(["render", scene, "-o", tmp_path / "x.npy"], capsys, f"no space left on device: {tmp_path / 'x.npy'}")


@pytest.mark.parametrize("stroke", ["-1", "nan", "inf", "0"])
def test_hidden_lines_stroke_must_be_a_positive_width(scene, tmp_path, capsys, stroke):
    out = tmp_path / "l.svg"
    refused(["hidden-lines", scene, "--stroke", stroke, "-o", out], capsys, "--stroke", written=[out])


# --- no JIT -------------------------------------------------------------------------


def test_every_kernel_is_compiled_ahead_and_no_jit_is_imported():
    # the kernels are C++ built at install: rendering with every method that
    # had a numba kernel loads no JIT compiler, so a fresh machine pays no compile
    code = ("import sys; from aaeval import registries; from aaeval.renderers import render;"
            "from aaeval.scenes import load_scene; registries.load();"
            "s = load_scene('configs/scenes/fan.toml');"
            "[render(s, m) for m in ('catmull', 'catmull:filter=mitchell', 'weiler-atherton', 'abuffer',"
            " 'supersample:k=4', 'jitter:k=2', 'msaa')];"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numba', 'llvmlite')))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
