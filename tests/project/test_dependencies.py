"""Every package the code and the tests import is declared: a dependency of aaeval, or in
its ``[test]`` extra. A new virtual environment gets exactly those (``pip install -e
".[test]"``), so an import that is only there because someone installed it by hand would
fail for the next person; this test fails first, in any environment."""

from __future__ import annotations

import ast
import re
import sys
import tomllib
from importlib import metadata
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: The folders whose imports must be installable from pyproject.toml alone.
CHECKED = ("aaeval", "tests", "examples", "benchmarks")
#: Modules the tests write themselves (a plugin module in a temporary folder).
WRITTEN_BY_TESTS = {"aaeval_callable_test_plugin"}
#: Optional packages: imported only where present, each with the reason it is optional.
OPTIONAL = {
    "pycvvdp": "ColorVideoVDP (the [cvvdp] extra) needs PyTorch; its metric is listed as unavailable without it",
    "torch": "ColorVideoVDP's runtime (the [cvvdp] extra)",
    "torchvision": "imported by ColorVideoVDP (the [cvvdp] extra)",
}


def _normal(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _declared() -> set[str]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    requirements = [*project["dependencies"], *project["optional-dependencies"]["test"]]
    return {_normal(re.match(r"[A-Za-z0-9_.-]+", r).group(0)) for r in requirements}


def _imports() -> dict[str, set[str]]:
    """Top-level module names imported anywhere in :data:`CHECKED`, with a file for each."""
    found: dict[str, set[str]] = {}
    for folder in CHECKED:
        for path in (ROOT / folder).rglob("*.py"):
            local = {p.stem for p in path.parent.glob("*.py")}
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                         [node.module] if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module else [])
                for name in names:
                    top = name.split(".")[0]
                    if top not in local:
                        found.setdefault(top, set()).add(str(path.relative_to(ROOT)))
    return found


@pytest.mark.slow
def test_every_import_is_a_declared_dependency():
    declared, owners = _declared(), metadata.packages_distributions()
    ours = {"aaeval", "tests", "__future__", *WRITTEN_BY_TESTS, *OPTIONAL}
    undeclared = {}
    for module, files in _imports().items():
        if module in ours or module in sys.stdlib_module_names:
            continue
        distributions = {_normal(d) for d in owners.get(module, [])}
        if not distributions & declared:
            undeclared[module] = (sorted(distributions) or ["not installed"], sorted(files)[:3])
    assert not undeclared, f"imported but not in pyproject.toml's dependencies or [test] extra: {undeclared}"


def test_tests_do_not_skip_a_missing_dependency():
    """A dependency that fails to import must fail the suite, not skip a test quietly."""
    for path in (ROOT / "tests").rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        for module in re.findall(r"importorskip\(\s*['\"]([\w.]+)", text):
            assert module.split(".")[0] in OPTIONAL, f"{path.relative_to(ROOT)} skips when {module} is missing"
