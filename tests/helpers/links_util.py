"""A tiny sweep in a world with files outside its folder, for the tests that plant links."""

from __future__ import annotations

import json
import os

from aaeval.cli import main
from tests.helpers.sweep_util import write_config

TINY = """
[experiment]
name = "tiny"
description = "link test sweep"
reference = "supersample:k=2"
metrics = ["rmse"]
temporal = ["sum_variation"]

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 2, size = 8}]
methods = ["point"]
"""


def world_of(tmp_path):
    """``outside/``: files and a folder a hostile link points at; ``out/``: the sweep folder."""
    outside = tmp_path / "outside"
    (outside / "dir").mkdir(parents=True)
    (outside / "victim.txt").write_text("KEEP\n")
    (outside / "dir" / "x.json").write_text('{"key": "x"}')
    config = write_config(tmp_path, TINY)
    return tmp_path, outside, config


def snapshot(folder):
    """Every path under ``folder`` with its kind and content (links not followed)."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            p = os.path.join(root, name)
            if os.path.islink(p):
                out[p] = ("link", os.readlink(p))
            elif os.path.isfile(p):
                with open(p, "rb") as f:
                    out[p] = ("file", f.read())
            else:
                out[p] = ("dir", None)
    return out


def sweep(tmp_path, config, *extra):
    return main(["sweep", str(config), "--out", str(tmp_path / "out"), "--workers", "1", "--quiet",
                 "--cache", str(tmp_path / "cache"), *extra])


MARKUP = "<script>alert('x')</script>"


def plant_markup(out) -> None:
    """Markup in every text field of every cell record and of the manifest of the sweep
    folder ``out`` (tests/report/test_hostile_report.py, scripts/hostile_run.py)."""
    fields = ["group", "scene", "scene_source", "difficulty_label", "method", "spec", "reference",
              "reference_kind", "host", "executor", "code_version", "error"]
    for cell in (out / "cells").glob("*.json"):
        record = json.loads(cell.read_text())
        record.update({f: MARKUP + f for f in fields}, failure="method")  # an error comes with its kind
        cell.write_text(json.dumps(record))
    manifest = json.loads((out / "manifest.json").read_text())
    manifest.update(experiment=MARKUP + "experiment", description=MARKUP + "description",
                    code_version=MARKUP + "code_version")
    for cell in manifest["cells"]:  # the manifest's copy must agree with the record's
        cell.update({f: MARKUP + f for f in ("group", "scene", "spec", "difficulty_label", "reference")})
    (out / "manifest.json").write_text(json.dumps(manifest))
