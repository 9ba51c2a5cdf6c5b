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
built-in. :func:`load_plugins` loads one group, once per process; it is called where the
built-in registries are filled (the end of :mod:`aaeval.renderers`, of
:mod:`aaeval.specular.methods`, and the start of the command line for metrics). A plugin
that fails to load (an import error, an exception while registering, a name registered
twice) is named in one line on stderr and skipped; the others load. See ``docs/plugins.md``.
"""

from __future__ import annotations

import sys
import threading
from importlib import metadata
from types import ModuleType

__all__ = ["GROUPS", "load_plugins", "load_all", "loaded", "failed"]

GROUPS = ("aaeval.methods", "aaeval.metrics", "aaeval.specular")

_lock = threading.RLock()
_done: set[str] = set()
_loaded: dict[str, list[str]] = {}
_failed: dict[str, list[str]] = {}


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
    """Load every entry point of ``group`` (once per process); returns the names loaded."""
    with _lock:
        if group in _done:
            return list(_loaded.get(group, []))
        _done.add(group)  # first: a plugin importing aaeval does not load the group again
        points = sorted(_entry_points(group), key=lambda e: e.name)
        if points:
            _builtins_first(group)
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
        _loaded[group] = names
        return list(names)


def _builtins_first(group: str) -> None:
    # the built-ins register before any plugin, so a plugin reusing a built-in name is the
    # one refused (a module already being imported is returned as it is)
    if group == "aaeval.methods":
        import aaeval.renderers  # noqa: F401
    elif group == "aaeval.specular":
        import aaeval.specular.methods  # noqa: F401
    elif group == "aaeval.metrics":
        import aaeval.metrics.registry  # noqa: F401


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
