"""The spec grammar: a string that names a method and sets its options.

``"catmull"``, ``"supersample:k=4"``, ``"mitsuba:spp=4096,seed=1"``: :func:`parse_spec`
splits the text; :class:`MethodSpec` checks the name against the registry
(:data:`aaeval.renderers.registry.METHODS`) and every option (type, range, rule), fails
loudly on anything unknown, and is the one canonical string and label of a spec.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any, Callable, Iterable, Mapping

from aaeval.renderers.registry import METHODS, Method, MethodError

__all__ = ["INCIDENTAL_OPTIONS", "MethodSpec", "format_spec", "parse_spec", "resolve"]


def parse_spec(spec: str) -> tuple[str, dict[str, str]]:
    """Split ``"name:key=value,key=value"`` into the name and raw option strings."""
    if not isinstance(spec, str) or not spec.strip():
        raise MethodError(f"empty method spec {spec!r}")
    name, _, rest = spec.strip().partition(":")
    options: dict[str, str] = {}
    for item in filter(None, (part.strip() for part in rest.split(","))):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise MethodError(f"method spec {spec!r}: option {item!r} is not key=value")
        if key.strip() in options:
            raise MethodError(f"method spec {spec!r}: option {key.strip()!r} given twice")
        options[key.strip()] = value.strip()
    return name.strip(), options


#: Specs parsed in this process, by their text (a method registered again is parsed anew).
_PARSED: dict[str, "MethodSpec"] = {}


class MethodSpec(str):
    """A method spec parsed and validated once: the canonical spec string, carrying the
    :class:`Method` it names (``.method``) and its full options, defaults filled in
    (``.options``, read-only).

    Make one with :meth:`parse` where a spec enters (the command line, a sweep config, a
    stored table) and pass it down: nothing below parses it again. It *is* its canonical
    string (the options that differ from the defaults, sorted: ``"catmull"`` and
    ``"catmull:specular=none"`` are both ``"catmull"``), so records, tables and stores
    keep plain strings; :meth:`label` is the one rule for the label shown to a reader.
    """

    method: Method
    options: Mapping[str, Any]

    @classmethod
    def parse(cls, spec: str, **overrides: Any) -> "MethodSpec":
        """The spec ``spec`` names (a string, or a MethodSpec returned as is), with
        ``overrides`` set; :class:`MethodError` (one line) for an unknown method, an
        unknown option or a value the option does not take."""
        if isinstance(spec, MethodSpec) and not overrides:
            return spec
        if not overrides:  # a spec's text is parsed once a process (the config, the table, a worker)
            known = _PARSED.get(str(spec))
            if known is not None and METHODS.get(known.method.name) is known.method:
                return known
        name, raw = parse_spec(str(spec))
        parsed = cls.of(name, {**raw, **overrides})
        if not overrides:
            _PARSED[str(spec)] = parsed  # the text as written, beside the canonical text
        return parsed

    @classmethod
    def of(cls, name: str, options: Mapping[str, Any]) -> "MethodSpec":
        """The spec of method ``name`` with ``options`` set (raw strings from a spec's text,
        as :func:`parse_spec` splits it, or values), checked as :meth:`parse` checks them."""
        method = METHODS.get(name)
        if method is None:
            raise MethodError(_unknown_method(name))
        defaults = {key: opt.default for key, opt in method.options.items()}
        return cls._checked(method, defaults, options)

    @classmethod
    def _checked(cls, method: Method, base: Mapping[str, Any], raw: Mapping[str, Any]) -> "MethodSpec":
        """``base`` (checked options) with ``raw`` converted and set: one :class:`MethodError`
        line for an unknown option or a value the option does not take."""
        name = method.name
        unknown = sorted(set(raw) - set(method.options))
        if unknown:
            allowed = ", ".join(sorted(method.options)) or "none"
            raise MethodError(f"method {name!r}: unknown option(s) {unknown}; options: {allowed}")
        options = dict(base)
        for key, value in raw.items():
            options[key] = method.options[key].convert(value, f"method {name!r} option {key!r}", MethodError)
        return cls._made(method, options)

    @classmethod
    def _made(cls, method: Method, options: Mapping[str, Any]) -> "MethodSpec":
        made = str.__new__(cls, _spec_text(method, options, shown=_differs))
        made.method = method
        made.options = MappingProxyType(dict(options))
        # its canonical text, as records and tables store it, needs no parsing again
        known = _PARSED.get(str(made))
        if known is None or known.method is not method:
            _PARSED[str(made)] = made
        return made

    @property
    def name(self) -> str:
        return self.method.name

    def with_options(self, **changes: Any) -> "MethodSpec":
        """This spec with ``changes`` set (checked as :meth:`parse` checks them)."""
        # the spec is parsed already: only the changes are checked (its text is not read again)
        return MethodSpec._checked(self.method, self.options, changes) if changes else self

    def label(self, keep: Iterable[str] = ()) -> str:
        """What a reader is shown: the method and the options that differ from their
        defaults, plus those named in ``keep`` (the ones that vary among the rows shown
        together), sorted; options that only say how a result was obtained
        (:data:`INCIDENTAL_OPTIONS`) are left out."""
        keep = set(keep)
        return _spec_text(self.method, self.options,
                          shown=lambda m, k, v: k not in INCIDENTAL_OPTIONS and (k in keep or _differs(m, k, v)))

    def __copy__(self) -> "MethodSpec":
        return self  # a value: nothing in it changes

    def __deepcopy__(self, memo) -> "MethodSpec":
        return self

    def __reduce__(self):
        # another process parses the string again (methods are functions, not data)
        return (_spec_from_text, (str(self),))


def _unknown_method(name: str) -> str:
    if not METHODS:  # nothing registered: the program never loaded the registries
        return (f"unknown method {name!r}: no method is registered in this process "
                "(call aaeval.registries.load() first)")
    return f"unknown method {name!r}; available: {', '.join(sorted(METHODS))}"


def _spec_from_text(text: str) -> MethodSpec | str:
    """A spec unpickled in another process: parsed there, or left a string when that
    process does not know the method (a worker without a plugin), so that the task that
    renders it fails with the MethodError, as a result, instead of the transfer."""
    try:
        return MethodSpec.parse(text)
    except MethodError:
        return text


#: Options that only say how a result was obtained, not what was rendered (left out of labels).
INCIDENTAL_OPTIONS = frozenset({"cache"})


def _differs(method: Method, key: str, value: Any) -> bool:
    return key not in method.options or method.options[key].default != value


def _spec_text(method: Method, options: Mapping[str, Any], shown: Callable[[Method, str, Any], bool]) -> str:
    keys = sorted(k for k, v in options.items() if shown(method, k, v))
    return method.name + "".join(f"{':' if i == 0 else ','}{k}={options[k]}" for i, k in enumerate(keys))


def resolve(spec: str, **overrides: Any) -> tuple[Method, dict[str, Any]]:
    """The method a spec names and its full, validated options (defaults filled in):
    :meth:`MethodSpec.parse`, unpacked."""
    parsed = MethodSpec.parse(spec, **overrides)
    return parsed.method, dict(parsed.options)


def format_spec(name: str, options: Mapping[str, Any]) -> str:
    """Canonical spec string of method ``name`` with ``options``: the :class:`MethodSpec`'s."""
    return MethodSpec.of(name, options)

