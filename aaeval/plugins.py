"""Methods, metrics and specular clamps from other packages, through entry points.

A package declares, in its ``pyproject.toml``::

    [project.entry-points."aaeval.methods"]
    my-method = "my_package.methods"          # a module: importing it registers
    [project.entry-points."aaeval.metrics"]
    my-metric = "my_package.metrics:register" # or a function, called with no arguments
    [project.entry-points."aaeval.specular"]
    my-clamp = "my_package.specular"

and, once installed, what it registers (``register_method``, ``register_metric``,
``register_specular``) is known to ``aaeval methods``, specs, sweeps and the report like a
built-in. :func:`load_plugins` loads one group, once per process; :func:`aaeval.registries.load`
calls it for every group (:func:`load_all`) after the built-ins are registered. A plugin
that fails to load (an import error, an exception while registering, a name registered
twice) is named in one line on stderr and skipped; the others load. See ``docs/plugins.md``.

A sweep cell whose method, metric or specular clamp comes from a plugin carries the
plugin's identity in its key (:func:`cell_plugins`: distribution name, version and a
digest of its module files), so an edited or upgraded plugin reruns its cells.
"""

from __future__ import annotations

import functools
import hashlib
import sys
import threading
from importlib import metadata
from pathlib import Path
from types import ModuleType
from typing import Any, Callable, Iterable

__all__ = ["GROUPS", "load_plugins", "load_all", "loaded", "failed", "plugin_identity", "cell_plugins"]

GROUPS = ("aaeval.methods", "aaeval.metrics", "aaeval.specular")

_lock = threading.RLock()
_done: set[str] = set()
_loaded: dict[str, list[str]] = {}
_failed: dict[str, list[str]] = {}
# top-level module of a loaded entry point -> (distribution name, version)
_distributions: dict[str, tuple[str, str]] = {}


_every: list = []


def _entry_points(group: str):
    # one scan of the installed distributions per process (~20 ms), not one per group
    if not _every:
        _every.append(metadata.entry_points())
    found = _every[0]
    if hasattr(found, "select"):
        return list(found.select(group=group))
    return list(found.get(group, ()))  # Python < 3.10: a dict of groups


def load_plugins(group: str) -> list[str]:
    """Load every entry point of ``group`` (once per process); returns the names loaded.

    The built-ins are expected registered first (:func:`aaeval.registries.load` does
    both, in that order), so that a plugin reusing a built-in name is the one refused.
    """
    with _lock:
        if group in _done:
            return list(_loaded.get(group, []))
        _done.add(group)  # first: a plugin importing aaeval does not load the group again
        points = sorted(_entry_points(group), key=lambda e: e.name)
        names: list[str] = []
        for ep in points:
            try:
                obj = ep.load()
                if not isinstance(obj, ModuleType) and callable(obj):
                    obj()
            except Exception as exc:  # a broken plugin must not stop aaeval or the others
                detail = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
                print(f"aaeval: plugin {ep.name!r} ({ep.value}) in {group} failed to load, skipped: "
                      f"{type(exc).__name__}{': ' + detail if detail else ''}", file=sys.stderr)
                _failed.setdefault(group, []).append(ep.name)
                continue
            names.append(ep.name)
            _note_distribution(ep)
        _loaded[group] = names
        return list(names)


def load_all() -> None:
    """Load every group (:data:`GROUPS`)."""
    for group in GROUPS:
        load_plugins(group)


def loaded(group: str) -> list[str]:
    """Names of the entry points of ``group`` loaded so far."""
    return list(_loaded.get(group, []))


def failed(group: str) -> list[str]:
    """Names of the entry points of ``group`` that failed to load."""
    return list(_failed.get(group, []))


# --- a plugin's identity, for the keys of sweep cells ---------------------------------

#: Files of a plugin package whose content is part of its identity (code, compiled code).
CODE_SUFFIXES = (".py", ".so", ".pyd")


def _note_distribution(ep) -> None:
    top = ep.value.split(":")[0].strip().split(".")[0]
    dist = getattr(ep, "dist", None)  # Python >= 3.10; before, the module names the plugin
    _distributions[top] = (dist.metadata["Name"] or dist.name, dist.version) if dist is not None else (top, "unknown")


@functools.lru_cache(maxsize=None)
def _files_digest(top: str) -> str:
    """sha256 over the code files of the top-level module ``top`` (path and content of each)."""
    module = sys.modules.get(top)
    if module is None:
        return "not-imported"
    if hasattr(module, "__path__"):  # a package: every code file below it
        files = sorted((f.relative_to(root).as_posix(), f) for root in map(Path, module.__path__)
                       for f in root.rglob("*") if f.suffix in CODE_SUFFIXES and "__pycache__" not in f.parts)
    else:
        path = Path(getattr(module, "__file__", "") or "")
        files = [(path.name, path)] if path.is_file() else []
    digest = hashlib.sha256()
    for name, path in files:
        digest.update(name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def plugin_identity(obj: Callable | None) -> dict[str, str] | None:
    """Who provides the registered function ``obj``: ``distribution``, ``version`` and
    ``files`` (a digest of the providing package's code files); None for aaeval's own.

    Only a package loaded through an entry point is a plugin: a function registered by
    hand (a test, a notebook cell) is None, as every process that runs the cell could not
    know it otherwise and would compute another key.
    """
    top = (getattr(obj, "__module__", None) or "").split(".")[0]
    if top not in _distributions:
        return None
    name, version = _distributions[top]
    return {"distribution": name, "version": version, "files": _files_digest(top)}


def cell_plugins(spec, metrics: Iterable[str] = ()) -> list[dict[str, str]]:
    """The plugins a cell depends on: its method's, its specular clamp's and its metrics'.

    Parameters
    ----------
    spec : MethodSpec
        The cell's method (its ``specular`` option, if any, names the clamp).
    metrics : iterable of str
        The metric names the cell computes.

    Returns
    -------
    plugins : list of dict
        Distinct :func:`plugin_identity` values, sorted; empty for built-ins only (a cell
        of built-ins keeps the key it always had).
    """
    from aaeval.metrics import METRICS
    from aaeval.renderers import METHODS

    used: list[Any] = [METHODS[spec.name].render]
    specular = spec.options.get("specular")
    if specular not in (None, "none"):
        from aaeval.specular.methods import SPECULAR_METHODS

        used.append(SPECULAR_METHODS[specular].clamp)
    used += [METRICS[name].func for name in metrics]
    found = {tuple(sorted(i.items())): i for i in map(plugin_identity, used) if i is not None}
    return [found[k] for k in sorted(found)]
