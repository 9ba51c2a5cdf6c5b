"""Every registry aaeval fills, loaded once per process by one explicit call: :func:`load`.

The registries are the rendering methods (:data:`aaeval.renderers.METHODS`), the specular
methods of ``catmull:specular=NAME`` (:data:`aaeval.specular.methods.SPECULAR_METHODS`),
the pixel filters (:data:`aaeval.filters.FILTERS`) and the metrics and masks
(:data:`aaeval.metrics.METRICS`). Importing a registry module gives the registry and the
entries its own module defines; the method modules of :mod:`aaeval.renderers` and the
plugins of other packages (:mod:`aaeval.plugins`) register only when :func:`load` runs.

:func:`load` is called where a program starts: the command line's ``main``, each sweep
worker (:mod:`aaeval.sweeps.local_workers`, :mod:`aaeval.sweeps.dask_executor`), and every
function of the public Python API (:mod:`aaeval.api`). Code below those (``aaeval.renderers.render``, a sweep's
``run_sweep``) expects it called; a program of its own calls it once first.
"""

from __future__ import annotations

import threading

__all__ = ["load", "loaded"]

_lock = threading.RLock()
_state = {"loaded": False}


def load() -> None:
    """Register every built-in method, specular method, filter and metric, then the plugins
    of every entry point group, in that order (a plugin reusing a built-in's name is the
    one refused); once per process, later calls return at once.

    A plugin that imports aaeval and calls :func:`load` while it is being loaded finds the
    registries as far as they are filled: the call returns, it does not start over.
    """
    with _lock:
        if _state["loaded"]:
            return
        _state["loaded"] = True
        try:
            _load_builtins()
            from aaeval.plugins import load_all

            load_all()
        except BaseException:
            _state["loaded"] = False  # a failed start (a missing kernel) is tried again, not hidden
            raise


def loaded() -> bool:
    """Whether :func:`load` has run (or is running) in this process."""
    return _state["loaded"]


def _load_builtins() -> None:
    # one import per method module of aaeval.renderers; each registers its methods
    # (in this order: the order `aaeval methods` lists them)
    from aaeval.renderers import (  # noqa: F401
        catmull,
        point,
        supersample,
        jitter,
        abuffer,
        skia_painter,
        blend2d_painter,
        mitsuba,
        weiler_atherton,
        freetype,
        resvg,
        msaa,
        fxaa,
        taa,
    )
    import aaeval.filters  # noqa: F401
    import aaeval.metrics.masks  # noqa: F401  (aaeval.metrics loads its names lazily: the modules that register)
    import aaeval.metrics.registry  # noqa: F401
    import aaeval.specular.methods  # noqa: F401
