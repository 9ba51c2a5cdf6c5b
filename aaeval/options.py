"""The one option type and the one registry shape every part of aaeval uses.

An :class:`Option` declares one setting a user may give: its type, its default, what it
means, and which values it takes (choices, an inclusive or open numeric range, a rule).
Methods (``supersample:k=4``), scene generators (``size = 24``) and the specular
methods' parameters (``catmull:specular=crow,k=4``) all declare theirs with it, and
:meth:`Option.convert` is the only place a raw value (a spec's string, a TOML number)
becomes a checked value.

A :class:`Registry` is a name -> entry table (a ``dict``) that refuses a name registered
twice, in one line, and can :meth:`~Registry.unregister` one. Every registry of aaeval
(methods, metrics, masks, pixel filters, scene generators, scene-file sections, specular
methods) is one, filled by its ``register_<kind>(name, ...)`` call; the ones whose
entry is a function also take that call as a decorator (``@register_method("toy",
summary=...)``). Tests that register a toy entry remove it with ``REGISTRY.unregister``.

This module imports nothing from aaeval.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, Callable, Iterable, TypeVar

__all__ = ["Option", "OptionError", "Registry", "MAX_INT"]

T = TypeVar("T")

#: The largest integer an ``int`` option takes: int64's, which native code and numpy hold.
MAX_INT = 2**63 - 1


class OptionError(ValueError):
    """A value an option does not take (wrong type, out of range, not a choice)."""


@dataclass(frozen=True)
class Option:
    """A declared option: its type, default and meaning, and the values it takes.

    ``minimum`` and ``maximum`` bound numbers (inclusive; ``low_open=True`` makes the
    minimum strict); ``choices`` lists the values taken (any container: a live
    ``dict.keys()`` view follows a registry); ``check(value)`` returns why a value is
    refused, or None. Float options are always finite; an ``int`` option takes integers
    only (an integral float such as ``3.0`` from a TOML file is one). ``words`` says the
    values taken as a user reads them (``"a whole number of threads from 1 to 4096"``):
    given, it is the rule, and every refusal reads ``WHERE: expected WORDS, got RAW``.
    """

    type: type
    default: Any
    doc: str = ""
    choices: Any = None
    minimum: float | None = None
    maximum: float | None = None
    check: Callable[[Any], str | None] | None = None
    low_open: bool = False
    words: str | None = None

    def rule(self) -> str:
        """The values taken, in words (``an integer in [1, 100000]``)."""
        if self.words is not None:
            return self.words
        if self.choices is not None:
            return f"one of {list(self.choices)}"
        kind = {int: "an integer", float: "a finite number"}.get(self.type, f"a {self.type.__name__}")
        low = None if self.minimum is None else f"{self.minimum:g}"
        high = None if self.maximum is None else f"{self.maximum:g}"
        if low is not None and high is not None:
            return f"{kind} in {'(' if self.low_open else '['}{low}, {high}]"
        if low is not None:
            return f"{kind} {'>' if self.low_open else '>='} {low}"
        if high is not None:
            return f"{kind} <= {high}"
        return kind

    def convert(self, raw: Any, where: str, error: type[Exception] = OptionError, *, text: bool = True) -> Any:
        """``raw`` (a string from a spec, or a value) as this option's type, checked;
        ``error`` (one line naming ``where``) when the option does not take it. With
        ``text=False`` (a value read from a typed file such as TOML) a string is never parsed
        as a number or a truth value."""
        value = _REFUSED if isinstance(raw, str) and self.type in _PARSED and not text else _coerce(raw, self.type)
        problem = self._problem(raw, value)
        if problem is not None:
            raise error(f"{where}: {problem if self.words is None else f'expected {self.words}, got {raw!r}'}")
        return value

    def _problem(self, raw: Any, value: Any) -> str | None:
        """Why this option does not take ``raw`` (``value``: it coerced to this option's type), or None."""
        if value is _REFUSED:
            return f"expected {self.type.__name__} ({self.rule()}), got {raw!r}"
        if self.type is int and abs(value) > MAX_INT:
            return (f"an integer of {value.bit_length()} bits, past the largest taken "
                    f"({MAX_INT}, what native code and numpy hold)")
        if self.choices is not None and value not in self.choices:
            return f"{value!r} is not one of {list(self.choices)}"
        if self.type in (int, float) and not self._in_range(value):
            return f"must be {self.rule()}, got {raw!r}"
        problem = self.check(value) if self.check is not None else None
        return f"{problem}, got {raw!r}" if problem else None

    def _in_range(self, value: float) -> bool:
        # an int compares with the bounds exactly, however long (a float of it may overflow)
        if isinstance(value, float) and not math.isfinite(value):
            return False
        if self.minimum is not None and not (value > self.minimum if self.low_open else value >= self.minimum):
            return False
        return self.maximum is None or value <= self.maximum


_REFUSED = object()
#: The types whose values a spec's text gives as strings, parsed.
_PARSED = (int, float, bool)


def _coerce(raw: Any, kind: type) -> Any:
    """``raw`` as ``kind`` (a spec's string parsed as a number or a truth value; an integral
    number as an int), or _REFUSED."""
    if isinstance(raw, str) and kind in _PARSED:
        if kind is bool:
            return {"1": True, "true": True, "yes": True, "on": True,
                    "0": False, "false": False, "no": False, "off": False}.get(raw.lower(), _REFUSED)
        try:
            return kind(raw)
        except (ValueError, OverflowError):  # past int's digit limit, or float's range
            return _REFUSED
    if not isinstance(raw, bool):
        if kind is float and isinstance(raw, numbers.Real):
            try:
                return float(raw)
            except OverflowError:  # an integer past float's range (a 400-digit TOML number)
                return _REFUSED
        if kind is int and isinstance(raw, numbers.Integral):
            return int(raw)
        if kind is int and isinstance(raw, numbers.Real) and math.isfinite(raw) and float(raw).is_integer():
            return int(raw)
    if isinstance(raw, kind) and not (kind in (int, float) and isinstance(raw, bool)):
        return raw
    return _REFUSED


class Registry(dict):
    """Entries by name, in registration order; a name is registered once.

    ``what`` names an entry in messages (``"method"``); ``error`` is the exception raised
    for a duplicate or an unknown name.
    """

    def __init__(self, what: str, error: type[Exception] = ValueError,
                 entries: Iterable[tuple[str, Any]] = ()):
        super().__init__()
        self.what = what
        self.error = error
        for name, entry in entries:
            self.add(name, entry)

    def add(self, name: str, entry: T) -> T:
        """Register ``entry`` under ``name``; refuses a name registered already."""
        if name in self:
            raise self.error(f"{self.what} {name!r} is registered twice")
        self[name] = entry
        return entry

    def unregister(self, name: str) -> Any:
        """Remove ``name`` and return its entry; refuses a name not registered."""
        if name not in self:
            raise self.error(f"{self.what} {name!r} is not registered")
        return self.pop(name)

    def get_entry(self, name: str) -> Any:
        """The entry ``name``; the error lists the registered names otherwise."""
        if name not in self:
            raise self.error(f"unknown {self.what} {name!r}; available: {', '.join(self)}")
        return self[name]
