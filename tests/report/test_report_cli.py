"""Small command-line promises: ``aaeval --version``, ``render -o`` into a missing folder
refused unless ``--mkdir``, ``render --scale N`` enlarging PNG pixels by nearest neighbour."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import aaeval
from aaeval.cli import main

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "configs" / "scenes" / "catmull_fig1.toml"


def _aaeval(*args, cwd=None):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "aaeval", *args], capture_output=True, text=True, env=env,
                          cwd=cwd)


def test_version():
    run = _aaeval("--version")
    assert run.returncode == 0 and run.stdout.strip() == f"aaeval {aaeval.__version__}"


def test_render_refuses_a_missing_folder(tmp_path, capsys):
    out = tmp_path / "missing" / "fig1.png"
    assert main(["render", str(SCENE), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "no such folder" in err and "--mkdir" in err and len(err.strip().splitlines()) == 1
    assert not out.parent.exists()
    assert main(["render", str(SCENE), "-o", str(out), "--mkdir"]) == 0
    assert out.is_file()


def test_render_scale_repeats_pixels(tmp_path):
    from PIL import Image

    small, big = tmp_path / "a.png", tmp_path / "b.png"
    assert main(["render", str(SCENE), "-o", str(small)]) == 0
    assert main(["render", str(SCENE), "-o", str(big), "--scale", "3"]) == 0
    a, b = np.asarray(Image.open(small)), np.asarray(Image.open(big))
    assert b.shape[:2] == (3 * a.shape[0], 3 * a.shape[1])
    assert np.array_equal(b, a.repeat(3, axis=0).repeat(3, axis=1))


def test_render_scale_is_for_png_only(tmp_path, capsys):
    assert main(["render", str(SCENE), "-o", str(tmp_path / "a.npy"), "--scale", "2"]) == 2
    assert "PNG" in capsys.readouterr().err
    assert main(["render", str(SCENE), "-o", str(tmp_path / "a.png"), "--scale", "0"]) == 2
