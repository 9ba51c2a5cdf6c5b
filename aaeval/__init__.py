"""aaeval: a research testbed for anti-aliasing quality.

The library functions (:mod:`aaeval.api`) are loaded on first use (PEP 562), so
``import aaeval`` stays cheap: ``aaeval.load_scene``, ``aaeval.render``,
``aaeval.compare``, ``aaeval.sweep``, ``aaeval.open_sweep``, ``aaeval.show``. See ``docs/python.md``.
"""

__version__ = "0.1.0"

_API = ("load_scene", "render", "compare", "sweep", "open_sweep", "Sweep", "ArgumentError", "SweepIncomplete", "show")

__all__ = ["__version__", *_API]


def __getattr__(name: str):
    if name in _API:
        from aaeval import api

        return getattr(api, name)
    raise AttributeError(f"module 'aaeval' has no attribute {name!r}")


def __dir__():
    return sorted([*globals(), *_API])
