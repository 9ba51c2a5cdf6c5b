"""Data that carries its own type: the rules that keep the package's boundaries typed.

- no module of aaeval is named ``experiments`` (that word is the studies' folder);
- no private name (``_x``) is imported from another module of aaeval;
- no decision matches an error's or a display column's text (status is data: the cell
  record's ``failure``, the summary's ``cluster_lost``, the references' ``validated``);
- a sweep parses each spec's text once.
"""

from __future__ import annotations

import ast
import collections
import re
from pathlib import Path

import aaeval

PACKAGE = Path(aaeval.__file__).parent
# The shapes a decision on text took: a prefix of an error, a "Name: " searched in a line,
# a verdict searched in a display column.
TEXT_DECISIONS = [
    re.compile(r"\berror\w*\s*\.\s*startswith\("),
    re.compile(r"""["'][A-Za-z]+(?:Lost|Died|Error|Exceeded): ["']\s+in\b"""),
    re.compile(r"""["']: (?:agrees|differs|DIFFERS) \(["']\s+in\b"""),
    re.compile(r"""\.startswith\(\s*\(?\s*["'](?:worker died|timed out)"""),
]


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        yield path, ast.parse(path.read_text(encoding="utf-8"))


def test_no_module_is_named_experiments():
    assert not [p for p in PACKAGE.rglob("experiments*") if "__pycache__" not in p.parts]


def test_no_private_name_is_imported_across_modules():
    found = []
    for path, tree in _modules():
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("aaeval"):
                found += [f"{path.relative_to(PACKAGE)}: {node.module}.{a.name}" for a in node.names
                          if a.name.startswith("_") and not a.name.startswith("__")]
    assert not found, found


def test_no_decision_reads_error_or_display_text():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            code = line.split("#", 1)[0]
            if any(p.search(code) for p in TEXT_DECISIONS):
                found.append(f"{path.relative_to(PACKAGE)}:{number}: {line.strip()}")
    assert not found, found


def test_a_sweep_parses_each_spec_once(tmp_path, monkeypatch):
    from aaeval.renderers import spec as spec_module
    from aaeval.sweeps import load_experiment, run_sweep
    from tests.helpers.sweep_util import SMALL, write_config

    monkeypatch.setattr(spec_module, "_PARSED", {})  # as in a new process
    calls = collections.Counter()
    parse = spec_module.parse_spec

    def counted(text):
        calls[text] += 1
        return parse(text)

    monkeypatch.setattr(spec_module, "parse_spec", counted)
    experiment = load_experiment(write_config(tmp_path, SMALL))
    run_sweep(experiment, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert calls and max(calls.values()) == 1, calls
