"""No import cycle in aaeval/: the import graph, every import counted, must be acyclic.

The rule, and why it is this one:

- An edge ``A -> B`` is any import statement in module ``A`` naming ``B``: at module
  level, inside ``try``/``if`` and class bodies, and inside functions too. An import
  inside a function runs later, so a cycle through one does not fail at import time,
  but it ties the two modules together all the same: neither can be read, tested or
  moved without the other, and which layer a function belongs to is left unsaid. The
  package is layered (scenes < native kernels < Catmull, Weiler-Atherton, specular <
  the renderers' registry and methods < metrics < ground truth < experiments < report,
  command line, API); a function whose imports point up a layer lives in the wrong module.
- Only ``if TYPE_CHECKING:`` blocks are left out: they never run, they name types for
  the reader.
- ``from P import name`` is an edge to ``P.name`` when that is a module, else to ``P``.
- Importing ``X.Y.Z`` also runs the ``__init__`` of ``X`` and ``X.Y``: those are edges
  too, except to the importing module's own ancestors (they are always loaded, or being
  loaded, before their children, so a child importing a sibling through its parent is
  not a cycle).

Registries are filled by one explicit call (:func:`aaeval.registries.load`), not by a
package importing its plugins, so no registry needs an import pointing back up.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

import aaeval
from tests.helpers.package_modules import aaeval_modules

ROOT = Path(aaeval.__file__).parent


_modules = aaeval_modules


def _imports(tree: ast.Module):
    """Every import statement of the module, in functions too; not under ``if TYPE_CHECKING:``."""

    def walk(nodes):
        for node in nodes:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                yield node
            elif isinstance(node, ast.If) and _is_type_checking(node.test):
                yield from walk(node.orelse)
            else:
                yield from walk(ast.iter_child_nodes(node))

    yield from walk(tree.body)


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _targets(node, module: str, is_package: bool, modules: dict[str, Path]) -> set[str]:
    if isinstance(node, ast.Import):
        names = [alias.name for alias in node.names]
    else:
        base = node.module or ""
        if node.level:
            package = module if is_package else module.rpartition(".")[0]
            for _ in range(node.level - 1):
                package = package.rpartition(".")[0]
            base = f"{package}.{base}" if base else package
        names = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names]
    out = set()
    for name in names:
        parts = name.split(".")
        for i in range(1, len(parts) + 1):
            target = ".".join(parts[:i])
            ancestor = module == target or module.startswith(target + ".")
            if target in modules and not ancestor:
                out.add(target)
    return out


def import_graph() -> dict[str, set[str]]:
    """module -> the aaeval modules it imports; a copy each call (a test may plant an edge)."""
    return {module: set(targets) for module, targets in _parsed_graph().items()}


@functools.cache  # parsing every module is most of these tests' time; the files do not change
def _parsed_graph() -> dict[str, frozenset[str]]:
    modules = _modules()
    graph = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(), str(path))
        is_package = path.name == "__init__.py"
        graph[module] = frozenset(t for node in _imports(tree) for t in _targets(node, module, is_package, modules))
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the graph as a list of modules (first == last), or None."""
    state: dict[str, int] = {}  # 1 on the stack, 2 done
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


@pytest.mark.slow
def test_the_imports_of_aaeval_have_no_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


@pytest.mark.slow
def test_the_cycle_finder_finds_a_planted_cycle():
    graph = import_graph()
    graph["aaeval.scenes.format"] = graph["aaeval.scenes.format"] | {"aaeval.renderers.catmull"}
    cycle = find_cycle(graph)
    assert cycle is not None and cycle[0] == cycle[-1]


def test_the_graph_sees_parent_packages_and_from_imports():
    graph = import_graph()
    # catmull imports aaeval.renderers.registry: its own parent is not an edge, the module is
    assert "aaeval.renderers.registry" in graph["aaeval.renderers.catmull"]
    assert "aaeval.renderers" not in graph["aaeval.renderers.catmull"]
    # the registries load the method modules ("from aaeval.renderers import (catmull, ...)")
    assert "aaeval.renderers.catmull" in graph["aaeval.registries"]


def test_the_graph_counts_imports_inside_functions_and_not_type_checking_blocks():
    tree = ast.parse("from typing import TYPE_CHECKING\n"
                     "if TYPE_CHECKING:\n    import aaeval.api\nelse:\n    import aaeval.options\n"
                     "def f():\n    from aaeval.scenes import Scene\n"
                     "class C:\n    def g(self):\n        import aaeval.imageio\n")
    modules = _modules()
    found = set().union(*(_targets(n, "aaeval.toy", False, modules) for n in _imports(tree)))
    assert found == {"aaeval.options", "aaeval.scenes", "aaeval.imageio"}  # "aaeval" is the toy's parent


def test_no_top_level_folder_shares_a_name_with_a_package_of_aaeval():
    # "experiments" once meant scripts, a package and a config folder; one name, one thing
    packages = {p.name for p in ROOT.iterdir() if (p / "__init__.py").is_file()}
    top = {p.name for p in ROOT.parent.iterdir() if p.is_dir() and not p.name.startswith(".")}
    assert packages, "no aaeval packages found"
    # the studies live in experiments/, the sweep engine in aaeval/sweeps/: no clash at all
    clash = packages & top
    assert not clash, f"top-level folders named like aaeval packages: {sorted(clash)}"
