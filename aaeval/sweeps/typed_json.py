"""Strict JSON that gives every float back: the one way aaeval writes JSON.

JSON has no NaN or infinity. Python's ``json`` writes them as bare ``NaN`` and
``Infinity``, which strict parsers refuse; writing them as ``null`` is strict but loses
them: a NaN noise ("not measured") and a ``None`` ("no such value") come back as the same
thing, and a perfect PSNR (infinite) comes back as "not measured". So a float that is not
finite is written as one of the strings ``"NaN"``, ``"Infinity"`` or ``"-Infinity"`` and
``null`` stays ``None``.

A reader that knows a field holds a float gets it back with :func:`decode_float` (for the
tags, Python's own ``float()`` gives the same answer, and so does JavaScript's
``Number()``); the field's schema, not the text, says where the tags may appear, so a
string field that happens to read ``"NaN"`` stays a string.
"""

from __future__ import annotations

import json
import math
from typing import Any, Mapping

__all__ = ["NON_FINITE", "encode", "dumps", "is_float_value", "decode_float", "TypedJSONError"]

#: The tag of each float that is not finite, and back.
NON_FINITE = {"NaN": math.nan, "Infinity": math.inf, "-Infinity": -math.inf}


class TypedJSONError(ValueError):
    """A stored value that is not of the type its field holds."""


def _tag(value: float) -> str:
    if math.isnan(value):
        return "NaN"
    return "Infinity" if value > 0 else "-Infinity"


def encode(obj: Any) -> Any:
    """``obj`` as plain JSON data: non-finite floats as their tags, numpy scalars and
    arrays as Python numbers and lists, tuples as lists, mapping keys as text."""
    # the plain types of a record or a manifest first, by exact type: most of a sweep's
    # writing time was spent asking each value whether it is a Mapping
    kind = type(obj)
    if kind is str or kind is int or kind is bool or obj is None:
        return obj
    if kind is float:
        return obj if math.isfinite(obj) else _tag(obj)
    if kind is dict:
        return {k if type(k) is str else str(k): encode(v) for k, v in obj.items()}
    if kind is list or kind is tuple:
        return [encode(v) for v in obj]
    return _encode_other(obj)


def _encode_other(obj: Any) -> Any:
    """:func:`encode` of anything but a plain ``str``, ``int``, ``bool``, ``float``, ``dict``,
    ``list``, ``tuple`` or ``None``."""
    import numpy as np

    if isinstance(obj, Mapping):
        return {str(k): encode(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [encode(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return encode(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return _tag(obj)
    return obj


def dumps(obj: Any, **kwargs) -> str:
    """Strict JSON text of ``obj`` (:func:`encode`; ``json.dumps`` options pass through)."""
    return json.dumps(encode(obj), allow_nan=False, **kwargs)


def is_float_value(value: Any) -> bool:
    """Whether ``value`` is a stored float: a JSON number (not a boolean) or a tag."""
    if isinstance(value, bool):
        return False
    return isinstance(value, (int, float)) or (isinstance(value, str) and value in NON_FINITE)


def decode_float(value: Any, *, where: str = "value", optional: bool = False) -> float | None:
    """The float a field stored (:func:`encode`); ``None`` only where ``optional``.

    Raises :class:`TypedJSONError` naming ``where`` for anything else (text, a list, a
    boolean, or ``null`` in a field that always has a number).
    """
    if value is None and optional:
        return None
    if not is_float_value(value):
        raise TypedJSONError(f"{where} must be a number, 'NaN', 'Infinity' or '-Infinity'"
                             f"{' or null' if optional else ''}, got {value!r:.40}")
    return NON_FINITE[value] if isinstance(value, str) else float(value)
