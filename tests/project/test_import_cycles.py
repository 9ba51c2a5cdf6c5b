"""No import cycle in aaeval/: the module-level import graph must be acyclic.

The rule, and why it is this one:

- An edge ``A -> B`` is an import that runs when module ``A`` is loaded: statements at
  module level, also inside ``try``/``if`` and class bodies, but not inside functions
  (they run later, when every module is loaded) nor under ``if TYPE_CHECKING:`` (never
  runs). A cycle of such imports is what makes a module see a half-initialised
  neighbour, depending on which one a user happens to import first.
- ``from P import name`` is an edge to ``P.name`` when that is a module, else to ``P``.
- Importing ``X.Y.Z`` also runs the ``__init__`` of ``X`` and ``X.Y``: those are edges
  too, except to the importing module's own ancestors (they are always loaded, or being
  loaded, before their children, so a child importing a sibling through its parent is
  not a cycle).

Function-level imports are allowed: the Catmull method, for example, calls the specular
renderer (which uses Catmull's visibility) through one.
"""

from __future__ import annotations

import ast
from pathlib import Path

import aaeval

ROOT = Path(aaeval.__file__).parent


def _modules() -> dict[str, Path]:
    out = {}
    for path in ROOT.rglob("*.py"):
        parts = ("aaeval",) + path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _load_time_imports(tree: ast.Module):
    """Import statements that run when the module is loaded."""

    def walk(body):
        for node in body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                yield node
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                continue
            elif isinstance(node, ast.If) and _is_type_checking(node.test):
                yield from walk(node.orelse)
            else:
                for field in ("body", "orelse", "finalbody", "handlers"):
                    yield from walk(getattr(node, field, []) or [])

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
    modules = _modules()
    graph = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(), str(path))
        is_package = path.name == "__init__.py"
        graph[module] = set()
        for node in _load_time_imports(tree):
            graph[module] |= _targets(node, module, is_package, modules)
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


def test_module_level_imports_of_aaeval_have_no_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


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
    # the renderers package imports its method modules ("from aaeval.renderers import catmull")
    assert "aaeval.renderers.catmull" in graph["aaeval.renderers"]


def test_no_top_level_folder_shares_a_name_with_a_package_of_aaeval():
    # "experiments" once meant scripts, a package and a config folder; one name, one thing
    packages = {p.name for p in ROOT.iterdir() if (p / "__init__.py").is_file()}
    top = {p.name for p in ROOT.parent.iterdir() if p.is_dir() and not p.name.startswith(".")}
    assert packages, "no aaeval packages found"
    # the one exception, asked for by issue 31 (item 6): the studies live in experiments/.
    # It holds sweep configs and READMEs, no Python, so it cannot be taken for (or shadow)
    # the package aaeval.experiments; Python in it, or any other clash, still fails
    clash = packages & top
    assert clash <= {"experiments"}, f"top-level folders named like aaeval packages: {sorted(clash - {'experiments'})}"
    for name in clash:
        code = sorted(str(p.relative_to(ROOT.parent)) for p in (ROOT.parent / name).rglob("*.py"))
        assert not code, f"{name}/ is named like the package aaeval.{name}: it may hold no Python, found {code}"
