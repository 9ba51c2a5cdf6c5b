"""Rendering methods, one module per method, all in one registry.

This package gives the registry and what renders with it: :data:`METHODS`,
:func:`register_method` (:mod:`aaeval.renderers.registry`), :class:`MethodSpec`
(:mod:`aaeval.renderers.spec`) and :func:`render` / :func:`render_timed` / :func:`warm_up`
(:mod:`aaeval.renderers.run`; the render budget they check first is
:mod:`aaeval.renderers.budget`, the image check after :mod:`aaeval.renderers.check`).
The method modules register when :func:`aaeval.registries.load` imports them (the
command line, sweep workers and the Python API call it), not when this package is
imported.
"""

from aaeval.renderers.registry import METHODS, Method, MethodError, Option, register_method
from aaeval.renderers.run import render, render_timed, warm_up
from aaeval.renderers.spec import MethodSpec, format_spec, parse_spec, resolve

__all__ = [
    "METHODS",
    "Method",
    "MethodError",
    "MethodSpec",
    "Option",
    "format_spec",
    "parse_spec",
    "register_method",
    "render",
    "render_timed",
    "resolve",
    "warm_up",
]
