"""The command line, run as a user would."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from aaeval.cli import main
from aaeval.imageio import load_image

SCENE = (Path(__file__).resolve().parents[1] / "data" / "scenes" / "triangle_on_blue.toml").read_text()


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    return path


@pytest.mark.parametrize("suffix", [".npy", ".png", ".exr"])
def test_render_writes_every_format(scene_file, tmp_path, suffix):
    out = tmp_path / f"out{suffix}"
    assert main(["render", str(scene_file), "--method", "catmull", "-o", str(out)]) == 0
    image = load_image(out)
    assert image.shape == (9, 12, 3)
    assert main(["render", str(scene_file), "-o", str(tmp_path / "ref.npy")]) == 0
    exact = np.load(tmp_path / "ref.npy")
    # .npy is lossless; .exr is float32; .png is 8-bit sRGB (coarsest near white)
    tolerance = {".npy": 0.0, ".exr": 1e-7, ".png": 0.01}[suffix]
    np.testing.assert_allclose(image, exact, atol=tolerance)


def test_render_stats_json_times_the_render_only(scene_file, tmp_path):
    stats = tmp_path / "stats.json"
    assert main(["render", str(scene_file), "--frame", "2", "-o", str(tmp_path / "a.npy"), "--stats", str(stats)]) == 0
    data = json.loads(stats.read_text())
    assert data["method"] == "catmull" and data["frame"] == 2
    assert 0.0 < data["render_s"] < 5.0


def test_bad_scene_fails_cleanly_and_keeps_existing_output(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[image]\nwidth = 4\nheight = 4\n[[polygons]]\ncolor = [1, 0, 0]\nvertices = [[0, 0, 0], [1, 1, 0]]\n")
    out = tmp_path / "out.npy"
    out.write_bytes(b"earlier result")
    assert main(["render", str(bad), "-o", str(out)]) == 2
    assert out.read_bytes() == b"earlier result"
    assert "polygons[0]" in capsys.readouterr().err


def test_bad_method_spec_is_refused(scene_file, tmp_path, capsys):
    assert main(["render", str(scene_file), "--method", "catmull:bogus=3", "-o", str(tmp_path / "x.npy")]) == 2
    assert "unknown option" in capsys.readouterr().err
    assert main(["render", str(scene_file), "--method", "nosuch", "-o", str(tmp_path / "x.npy")]) == 2
    assert not (tmp_path / "x.npy").exists()


def test_invariance_command_reports_constant_sum(scene_file, capsys):
    assert main(["invariance", str(scene_file), "--method", "catmull"]) == 0
    out = capsys.readouterr().out
    variation = float(out.strip().splitlines()[-1].split()[-1])
    assert variation < 1e-12
    assert out.count("frame") >= 4


def test_console_entry_point_help():
    result = subprocess.run([sys.executable, "-m", "aaeval", "--help"], capture_output=True, text=True,
                            cwd=Path(__file__).parents[2])
    assert result.returncode == 0
    assert "render" in result.stdout and "invariance" in result.stdout


def test_canonical_spec_leaves_out_defaults():
    from aaeval.renderers import format_spec, resolve

    def canonical(spec):
        method, options = resolve(spec)
        return format_spec(method.name, options)

    assert canonical("catmull") == canonical("catmull:specular=none") == "catmull"
    assert canonical("supersample:k=8") == "supersample:k=8"
    assert canonical("supersample:k=4") == "supersample"
