"""The report draws what the sweep stored: nothing it can import renders or measures.

Every import counts here, function-level ones too (as in the cycle rule of
tests/project/test_import_cycles.py): a function-level import of a renderer is still a
renderer the report can run. Starting from every module of
``aaeval/report`` and ``aaeval/cli/report.py``, the walk follows each import to the module
it names and every package ``__init__`` on the way, transitively; no module that renders,
measures or parses scenes may be reached. And ``aaeval/metrics`` imports no renderer, ground
truth or sweep code: the masks it is given are rendered by the sweep's measuring step.
"""

from __future__ import annotations

import ast
import functools
import importlib
from pathlib import Path

import pytest

import aaeval
from tests.helpers.package_modules import aaeval_modules

ROOT = Path(aaeval.__file__).parent

#: Modules (and packages: every module under them) that render, measure or parse scenes.
FORBIDDEN = ("aaeval.groundtruth", "aaeval.catmull", "aaeval.weiler_atherton", "aaeval.native",
             "aaeval.metrics.masks", "aaeval.specular.shading", "aaeval.specular.exact", "aaeval.specular.render",
             "aaeval.renderers", "aaeval.scenes", "aaeval.sweeps.measure", "aaeval.sweeps.config",
             "aaeval.sweeps.runner", "aaeval.filters", "aaeval.plugins")


_modules = aaeval_modules


MODULES = _modules()


def _names(node, package: str) -> list[str]:
    """The dotted names an import statement loads, relative imports resolved."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    base = node.module or ""
    if node.level:
        anchor = package
        for _ in range(node.level - 1):
            anchor = anchor.rpartition(".")[0]
        base = f"{anchor}.{base}" if base else anchor
    return [f"{base}.{alias.name}" if f"{base}.{alias.name}" in MODULES else base for alias in node.names]


def _with_packages(names) -> set[str]:
    out = set()
    for name in names:
        parts = name.split(".")
        out.update(".".join(parts[:i]) for i in range(1, len(parts) + 1) if ".".join(parts[:i]) in MODULES)
    return out


# each walk below reads the same modules: parsed once per test process (the files do not change)
@functools.cache
def _parse(module: str):
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    return ast.parse(path.read_text()), package


@functools.cache
def _lazy(module: str) -> frozenset[str]:
    """What a package's PEP 562 ``__getattr__`` imports: loaded only when a name it serves is
    asked for (``from aaeval import render``, ``aaeval.render``), not by importing the package.
    A ``__getattr__`` written out is read from its imports; one made by
    :func:`aaeval._lazy.lazy_names` names its modules (``module_of``)."""
    tree, package = _parse(module)
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and node.name == "__getattr__":
            return frozenset(_with_packages(n for sub in ast.walk(node) if isinstance(sub, (ast.Import, ast.ImportFrom))
                                            for n in _names(sub, package)))
    served = getattr(getattr(importlib.import_module(module), "__getattr__", None), "module_of", None)
    if served is not None:
        return frozenset(_with_packages(f"{module}.{sub}" for sub in set(served.values())) | {"aaeval._lazy"})
    return frozenset()


@functools.cache
def _imports(module: str) -> frozenset[str]:
    """Every aaeval module an import anywhere in ``module`` loads (its packages' ``__init__``
    too), and what a lazy package serves where ``module`` asks it for a name."""
    tree, package = _parse(module)
    served = {sub for node in tree.body if isinstance(node, ast.FunctionDef) and node.name == "__getattr__"
              for sub in ast.walk(node)}
    names, asked = [], set()
    bound = {}  # local name -> package, for attribute access (``aaeval.render``)
    for node in ast.walk(tree):
        if node in served:
            continue
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            loaded = _names(node, package)
            names += loaded
            if isinstance(node, ast.ImportFrom):
                # a name (not a submodule) asked of a package: what its lazy __getattr__ serves
                asked.update(n for n, alias in zip(loaded, node.names)
                             if alias.name == "*" or not n.endswith("." + alias.name))
            else:
                bound.update({alias.asname or alias.name.split(".")[0]: alias.asname and alias.name
                              or alias.name.split(".")[0] for alias in node.names})
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in bound
                and not node.attr.startswith("__") and f"{bound[node.value.id]}.{node.attr}" not in MODULES):
            asked.add(bound[node.value.id])
    out = _with_packages(names)
    for name in asked:
        if name in MODULES:
            out |= _lazy(name)
    return frozenset(out - {module})


def reachable(starts) -> dict[str, str]:
    """Every module reachable from ``starts``, each with the module that first imported it."""
    seen = {s: "" for s in starts}
    todo = list(starts)
    while todo:
        module = todo.pop()
        for target in _imports(module):
            if target not in seen:
                seen[target] = module
                todo.append(target)
    return seen


def _path(seen: dict[str, str], module: str) -> str:
    chain = [module]
    while seen[chain[-1]]:
        chain.append(seen[chain[-1]])
    return " <- ".join(chain)


def _forbidden(seen: dict[str, str], banned) -> list[str]:
    return sorted(_path(seen, m) for m in seen if any(m == b or m.startswith(b + ".") for b in banned))


@pytest.mark.slow
def test_the_walk_sees_function_level_imports():
    """The walk is not blind where the old rule was: a function-level import is an edge."""
    assert "aaeval.catmull" in reachable(["aaeval.sweeps.measure"])  # measure imports Catmull in a function
    assert _forbidden(reachable(["aaeval.api"]), FORBIDDEN)


def test_the_report_reaches_nothing_that_renders_or_measures():
    starts = [m for m in MODULES if m == "aaeval.report" or m.startswith("aaeval.report.")]
    starts.append("aaeval.cli.report")
    assert _forbidden(reachable(starts), FORBIDDEN) == []


def test_metrics_import_no_renderer_ground_truth_or_sweep():
    """Every import statement of aaeval/metrics, function-level ones too: a mask read from a
    render is given that render by the sweep's measuring step (what the modules they import
    in turn reach is their packages' affair: tests/project/test_import_cycles.py)."""
    banned = ("aaeval.renderers", "aaeval.groundtruth", "aaeval.sweeps")
    found = [f"{m} imports {t}" for m in MODULES if m == "aaeval.metrics" or m.startswith("aaeval.metrics.")
             for t in _imports(m) if any(t == b or t.startswith(b + ".") for b in banned)]
    assert found == []
