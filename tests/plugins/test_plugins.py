"""Methods, metrics and specular clamps as plugins.

The example package in examples/aaeval-plugin-example is "installed" by a dist-info
folder holding its entry points (read from its pyproject.toml) on PYTHONPATH, as pip
would leave it, without running pip; aaeval then runs in a subprocess.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from importlib import metadata
from pathlib import Path

import pytest

from tests.helpers.plugin_util import fake_install

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "aaeval-plugin-example"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    site = tmp_path_factory.mktemp("site")
    project = tomllib.loads((EXAMPLE / "pyproject.toml").read_text())["project"]
    fake_install(site, project["name"], project["entry-points"])
    # two broken plugins: one raises on import, one names a module that does not exist
    (site / "aaeval_broken_plugin.py").write_text("raise RuntimeError('boom: this plugin is broken')\n")
    fake_install(site, "aaeval-broken-plugin", {"aaeval.methods": {"broken": "aaeval_broken_plugin"},
                                                "aaeval.metrics": {"missing": "aaeval_no_such_module_here"}})
    return site


def run(site: Path, *args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(site), str(EXAMPLE), str(ROOT), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "aaeval", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def plugin_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("aaeval: plugin ")]


def test_methods_lists_the_plugin_and_names_the_broken_ones(site):
    done = run(site, "methods")
    assert done.returncode == 0, done.stderr
    assert "blur: example plugin" in done.stdout and "strength=1.0 (float)" in done.stdout
    assert "catmull" in done.stdout and "msaa" in done.stdout  # the built-ins are all there
    assert "'halve'" in done.stdout  # the specular plugin is a choice of catmull's specular option
    lines = plugin_lines(done.stderr)
    assert len(lines) == 2, done.stderr
    assert any("'broken'" in line and "RuntimeError: boom" in line and "skipped" in line for line in lines)
    assert any("'missing'" in line and "aaeval_no_such_module_here" in line for line in lines)


def test_plugin_method_and_metric_through_compare(site, tmp_path):
    out = tmp_path / "fan.json"
    done = run(site, "compare", "configs/scenes/fan.toml", "-m", "blur:strength=0.5", "-m", "point", "-r",
               "catmull", "--metric", "rmse", "--metric", "max_abs_error", "--format", "json", "--json", str(out))
    assert done.returncode == 0, done.stderr
    rows = {row["method"]: row for row in json.loads(out.read_text())["rows"]}
    assert set(rows) == {"blur:strength=0.5", "point"}
    for row in rows.values():
        assert row["error"] is None and row["rmse"] > 0
        assert row["rmse"] <= row["max_abs_error"] <= 1
    assert rows["blur:strength=0.5"]["rmse"] != rows["point"]["rmse"]


@pytest.mark.slow
def test_plugin_through_a_sweep_and_the_report(site, tmp_path):
    config = tmp_path / "plugin.toml"
    config.write_text(f"""
[experiment]
name = "plugin"
reference = "catmull"
metrics = ["rmse", "max_abs_error"]
temporal = ["flicker"]
primary = "rmse"

[[groups]]
name = "edges"
scenes = ["{ROOT / 'configs' / 'scenes' / 'picket_fence.toml'}"]
methods = ["point", "blur"]
frames = [0, 1]
options.blur = {{ strength = [0.5, 1.0] }}
""")
    out = tmp_path / "sweep"
    done = run(site, "sweep", str(config), "--out", str(out), "--workers", "1")
    assert done.returncode == 0, done.stderr
    cells = [json.loads(p.read_text()) for p in (out / "cells").glob("*.json")]
    specs = {c["spec"] for c in cells}
    assert {"blur:strength=0.5", "blur", "point"} <= specs, specs
    assert all(c["error"] is None for c in cells), [c["error"] for c in cells if c["error"]]
    done = run(site, "report", str(out), "--png-only")  # only the page is read
    assert done.returncode == 0, done.stderr
    page = (out / "index.html").read_text()
    assert "blur:strength=0.5" in page and ("max_abs_error" in page or "max |error|" in page)


def test_a_broken_plugin_is_named_and_skipped_in_process(tmp_path, monkeypatch, capsys):
    from aaeval import plugins

    (tmp_path / "aaeval_good_test_plugin.py").write_text("LOADED = True\n")
    (tmp_path / "aaeval_bad_test_plugin.py").write_text("raise ImportError('needs a library not installed')\n")
    (tmp_path / "aaeval_callable_test_plugin.py").write_text(
        "CALLS = []\ndef register():\n    CALLS.append(1)\ndef fails():\n    raise ValueError('bad\\nsecond line')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    group = "aaeval.test-only-group"
    points = [metadata.EntryPoint("a-bad", "aaeval_bad_test_plugin", group),
              metadata.EntryPoint("b-good", "aaeval_good_test_plugin", group),
              metadata.EntryPoint("c-call", "aaeval_callable_test_plugin:register", group),
              metadata.EntryPoint("d-fails", "aaeval_callable_test_plugin:fails", group)]
    monkeypatch.setattr(plugins, "_entry_points", lambda g: points if g == group else [])
    assert plugins.load_plugins(group) == ["b-good", "c-call"]
    assert plugins.failed(group) == ["a-bad", "d-fails"]
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2, err
    assert "'a-bad'" in err[0] and "ImportError: needs a library not installed" in err[0]
    assert "'d-fails'" in err[1] and err[1].endswith("ValueError: bad")
    import aaeval_callable_test_plugin

    assert aaeval_callable_test_plugin.CALLS == [1]
    assert plugins.load_plugins(group) == ["b-good", "c-call"]  # once per process
    assert aaeval_callable_test_plugin.CALLS == [1]
