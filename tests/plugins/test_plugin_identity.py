"""Plugins are part of a cell's identity: the key of a cell whose method
comes from a plugin holds the plugin's distribution, version and a digest of its code, so an
edited plugin reruns its cells (and ``--dry-run`` says so), and an unedited one does not.

The plugin is "installed" as in tests/plugins/test_plugins.py (a dist-info folder on PYTHONPATH)
and aaeval runs in subprocesses, each a fresh interpreter as a real rerun would be.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from tests.helpers.plugin_util import fake_install

ROOT = Path(__file__).resolve().parents[2]

PLUGIN = '''
import numpy as np
from aaeval.renderers import register_method

@register_method("grey", summary="test plugin: a flat grey image")
def render_grey(scene):
    return np.full(scene.shape, {level})
'''

CONFIG = """
[experiment]
name = "grey"
reference = "catmull"
metrics = ["rmse"]
temporal = []

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 2, size = 8}]
methods = ["grey", "point"]
"""


def aaeval(site: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT), os.environ.get("PYTHONPATH", "")])}
    return subprocess.run([sys.executable, "-m", "aaeval", *args], env=env, capture_output=True, text=True,
                          timeout=300)


def grey_sums(out: Path) -> dict[int, float]:
    cells = [json.loads(p.read_text()) for p in (out / "cells").glob("*.json")]
    return {c["frame"]: c["intensity_sum"] for c in cells if c["spec"] == "grey"}


@pytest.fixture
def site(tmp_path) -> Path:
    site = tmp_path / "site"
    site.mkdir()
    (site / "aaeval_grey_plugin.py").write_text(PLUGIN.format(level=0.25))
    fake_install(site, "aaeval-grey-plugin", {"aaeval.methods": {"grey": "aaeval_grey_plugin"}})
    return site


@pytest.mark.slow
def test_an_edited_plugin_reruns_its_cells_only(site, tmp_path):
    config = tmp_path / "grey.toml"
    config.write_text(CONFIG)
    out = tmp_path / "out"
    first = aaeval(site, "sweep", str(config), "--out", str(out), "--workers", "1", "--quiet")
    assert first.returncode == 0, first.stderr
    assert grey_sums(out) == {0: 0.25 * 8 * 8 * 3, 1: 0.25 * 8 * 8 * 3}
    again = aaeval(site, "sweep", str(config), "--out", str(out), "--workers", "1", "--quiet")
    assert "4 cells, 4 already done, 0 run" in again.stdout, again.stdout  # same code: same keys

    (site / "aaeval_grey_plugin.py").write_text(PLUGIN.format(level=0.75))
    dry = aaeval(site, "sweep", str(config), "--out", str(out), "--dry-run")
    assert dry.returncode == 0, dry.stderr
    assert "plugin aaeval-grey-plugin 0.1.0 (code " in dry.stdout
    assert "2 finished cell(s) rerun: plugin changed, aaeval-grey-plugin 0.1.0" in dry.stdout, dry.stdout
    assert "2/4 done" in dry.stdout or "2 done" in dry.stdout, dry.stdout  # the point cells stay done

    second = aaeval(site, "sweep", str(config), "--out", str(out), "--workers", "1", "--quiet")
    assert "4 cells, 2 already done, 2 run" in second.stdout, second.stdout
    results = pd.read_parquet(out / "results.parquet")
    grey = results[results["spec"] == "grey"]
    assert sorted(grey["intensity_sum"]) == [0.75 * 8 * 8 * 3] * 2  # the new code's cells, only those

    metadata = next(site.glob("aaeval_grey_plugin-*.dist-info")) / "METADATA"
    metadata.write_text(metadata.read_text().replace("Version: 0.1.0", "Version: 0.2.0"))
    dry = aaeval(site, "sweep", str(config), "--out", str(out), "--dry-run")
    assert "2 finished cell(s) rerun: plugin changed, aaeval-grey-plugin 0.1.0" in dry.stdout, dry.stdout
    assert "-> aaeval-grey-plugin 0.2.0" in dry.stdout, dry.stdout


def test_builtins_have_no_plugin_identity():
    from aaeval.plugins import cell_plugins, plugin_identity
    from aaeval.renderers import METHODS, MethodSpec

    assert plugin_identity(METHODS["catmull"].render) is None  # aaeval's own: code_version covers it
    assert cell_plugins(MethodSpec.parse("catmull:specular=amanatides"), ["rmse", "edge_rmse"]) == []
