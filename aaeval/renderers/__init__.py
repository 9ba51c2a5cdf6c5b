"""Rendering methods, one module per method, all in one registry.

This package gives the registry (:mod:`aaeval.renderers.registry`): :data:`METHODS`,
:func:`register_method`, :class:`MethodSpec` and :func:`render` / :func:`render_timed` / :func:`warm_up`.
The method modules register when :func:`aaeval.registries.load` imports them (the
command line, sweep workers and the Python API call it), not when this package is
imported.
"""

from aaeval.renderers.registry import (
    METHODS,
    Method,
    MethodError,
    MethodSpec,
    Option,
    format_spec,
    parse_spec,
    register_method,
    render,
    render_timed,
    resolve,
    warm_up,
)

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
