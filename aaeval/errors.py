"""The Python API's error for an argument it does not take (shared by :mod:`aaeval.api` and
:mod:`aaeval.preview`)."""

from __future__ import annotations

__all__ = ["ArgumentError"]


class ArgumentError(TypeError, ValueError):
    """An argument of the Python API of the wrong type or outside the values it takes: one
    line naming the argument and what it takes. A ``TypeError`` and a ``ValueError``, so
    that either ``except`` catches it; the checks run before any file is read or rendered.
    (A value of the right type that breaks a rule of its content, a scene file or a method
    spec, raises that content's own error: ``SceneError``, ``MethodError``, ...)"""
