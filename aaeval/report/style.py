"""One look per method, for every figure of the report: the only place a method's colour,
marker and line style are chosen.

Colours are the Okabe-Ito / Tol colour-blind-safe palettes; every method also has its own
marker and dash pattern so that figures stay readable in greyscale. A method's options
never change its colour family or marker:

- a numeric option ladder (``supersample:k=2..16``, ``mitsuba:spp=4..1024``) is drawn in
  shades of the method's colour, light for the smallest value and dark for the largest,
  with markers growing along the ladder;
- a categorical option (``catmull:specular=none|amanatides|...``) gives each choice its own
  colour of the method's family (the hue turned a little and the lightness stepped, in the
  order the method declares its choices) and its own marker fill (full, none, left, right,
  bottom, top), so every clamp is told apart by colour as well as by marker;
- ``weiler-atherton``, the second exact road, is drawn hollow and larger and above
  ``catmull``: where the two coincide both stay visible.

:class:`Styles` is built once per report from every spec the report shows, so that a spec
has the same shade in every group, and legends list specs in one order: by method, then by
option value.
"""

from __future__ import annotations

import colorsys
import hashlib
import json
from dataclasses import dataclass
from typing import Iterable, Mapping

from matplotlib.colors import to_rgb

__all__ = ["METHOD_STYLES", "MethodStyle", "SpecStyle", "Styles", "method_style", "ground_truth_style"]


@dataclass(frozen=True)
class MethodStyle:
    colour: str
    marker: str
    dashes: tuple  # matplotlib dash pattern; () = solid
    hollow: bool = False  # drawn as a larger empty marker above the others (it coincides with one)


# The one table. Exact methods are blues, sampling methods warm colours, the ground
# truth's renderer olive, other rasterizers black, indigo and brown; markers and dashes
# differ for every method. A new method gets its line here.
METHOD_STYLES: dict[str, MethodStyle] = {
    "catmull": MethodStyle("#0072B2", "o", ()),
    "weiler-atherton": MethodStyle("#56B4E9", "s", (6, 2), hollow=True),
    "catmull-jagged": MethodStyle("#44AA99", "<", (1, 1.5)),
    "point": MethodStyle("#D55E00", "v", (4, 1.5, 1, 1.5)),
    "supersample": MethodStyle("#E69F00", "^", (3, 1.5)),
    "jitter": MethodStyle("#CC79A7", "D", (8, 2, 1, 2)),
    "abuffer": MethodStyle("#009E73", "P", (2, 2)),
    "skia": MethodStyle("#000000", "X", (5, 1, 1, 1, 1, 1)),
    "blend2d": MethodStyle("#777777", "x", (2, 1, 5, 1)),
    "mitsuba": MethodStyle("#999933", "h", (1, 3)),
    "freetype": MethodStyle("#332288", "*", (3, 1, 1, 1)),
    "resvg": MethodStyle("#661100", "d", (6, 1.5, 1, 1.5, 1, 1.5)),
    "msaa": MethodStyle("#882255", "p", (4, 1, 4, 3)),
    "fxaa": MethodStyle("#AA4499", "H", (1, 1, 1, 3)),
    "taa": MethodStyle("#117733", ">", (7, 1.5, 2, 1.5)),
}

_SPARE_COLOURS = ["#88CCEE", "#DDCC77", "#6699CC", "#EE8866", "#BBBBBB", "#44BB99"]
_SPARE_MARKERS = ["8", "1", "2", "3", "4", "+"]
_FILLS = ["full", "none", "left", "right", "bottom", "top"]
GROUND_TRUTH_COLOUR = "#555555"


def method_style(method: str) -> MethodStyle:
    """The style of a method; a method this table does not know yet gets a fixed one chosen
    from spare colours and markers by a hash of its name (the same in every figure)."""
    if method in METHOD_STYLES:
        return METHOD_STYLES[method]
    h = int(hashlib.sha256(method.encode()).hexdigest(), 16)
    return MethodStyle(_SPARE_COLOURS[h % len(_SPARE_COLOURS)], _SPARE_MARKERS[(h // 8) % len(_SPARE_MARKERS)],
                       (2, 1, 2, 3))


def ground_truth_style() -> dict:
    """Line keywords of the ground truth in curves (thick, grey, behind the methods)."""
    return {"color": GROUND_TRUTH_COLOUR, "lw": 3.0, "alpha": 0.45, "zorder": 1}


@dataclass(frozen=True)
class SpecStyle:
    method: str
    options: str  # canonical JSON of the options: with the method, names the spec
    colour: tuple
    marker: str
    fillstyle: str
    size: float
    dashes: tuple
    hollow: bool = False

    def line(self) -> dict:
        """Keywords for ``ax.plot`` (line and markers), tagged with the method for checks."""
        kw = {"color": self.colour, "marker": self.marker, "fillstyle": self.fillstyle, "ms": self.size,
              "mec": _edge(self.colour), "mew": 0.6, "ls": (0, self.dashes) if self.dashes else "-",
              "lw": 1.2, "gid": self.gid}
        if self.hollow:  # an empty, larger marker in its own colour, above the method it coincides with
            kw.update(mec=self.colour, mew=1.6, zorder=3)
        return kw

    gid: str = ""  # tag of this spec's artists (kept as SVG ids): ``method=NAME;options=k=v,k=v``

    def point(self) -> dict:
        """Keywords for a marker-only ``ax.plot``."""
        kw = self.line()
        kw.update(ls="none")
        return kw


def _edge(colour) -> str:
    """Marker edge: black on light fills, white on very dark ones (greyscale contrast)."""
    r, g, b = to_rgb(colour)
    return "white" if 0.2126 * r + 0.7152 * g + 0.0722 * b < 0.12 else "black"


def _shade(colour: str, t: float) -> tuple:
    """``colour`` lightened (t = 0) or darkened (t = 1) without changing its hue."""
    h, l, s = colorsys.rgb_to_hls(*to_rgb(colour))
    lo, hi = min(l, 0.25), min(0.68, max(l, 0.6))
    light = hi + (lo - hi) * t
    return colorsys.hls_to_rgb(h, light, s)


def _choice_colour(colour: str, i: int, n: int) -> tuple:
    """Choice ``i`` of ``n`` of a categorical option: the family's hue turned by -0.02 to
    +0.08 and its lightness stepped between dark and middle, so neighbours differ in both (the
    steps chosen for the largest smallest CIELAB distance between every registered method and
    specular clamp)."""
    h, l, s = colorsys.rgb_to_hls(*to_rgb(colour))
    turn = 0.0 if n <= 1 else (i / (n - 1) - 0.5) * 0.10 + 0.03
    light = (0.18, 0.30, 0.42, 0.24, 0.36, 0.48)[i % 6] if n > 1 else l
    return colorsys.hls_to_rgb((h + turn) % 1.0, light, min(1.0, max(s, 0.75)))


def _numeric(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Styles:
    """The styles of every spec one report shows (a spec: method plus its options)."""

    def __init__(self, specs: Iterable[tuple[str, dict]], choices: Mapping[str, Mapping[str, list]] | None = None,
                 texts: Mapping[tuple[str, str], dict] | None = None):
        """``specs``: (method, options) pairs; ``choices``: each method's declared choices per
        categorical option (their order orders the colours); ``texts``: the options of each
        (method, ``options`` column text) of the tables, so rows name a spec by that text."""
        self._options: dict[str, dict] = {}
        self._choices = {m: {k: list(v) for k, v in c.items()} for m, c in (choices or {}).items()}
        self._texts = dict(texts or {})
        ladders: dict[tuple[str, str], set] = {}
        for method, options in specs:
            opts = dict(options)
            self._options[_key(method, opts)] = opts
        by_method: dict[str, list[dict]] = {}
        for key, opts in self._options.items():
            by_method.setdefault(key.split("|", 1)[0], []).append(opts)
        self._varying: dict[str, list[str]] = {}
        for method, all_opts in by_method.items():
            keys = sorted({k for o in all_opts for k in o if len({json.dumps(p.get(k)) for p in all_opts}) > 1})
            self._varying[method] = keys
            for k in keys:
                ladders[(method, k)] = {o.get(k) for o in all_opts}
        self._ladders = ladders

    @classmethod
    def from_sweep(cls, stored: Mapping) -> "Styles":
        """The styles of a sweep's specs as it stored them (``specs.json``)."""
        specs = stored.get("specs", {})
        texts = {(method, text): opts for method, by_text in specs.items() for text, opts in by_text.items()}
        return cls([(method, opts) for (method, _), opts in texts.items()], stored.get("choices", {}), texts)

    def options(self, method: str, options) -> dict:
        """The options of a spec named by its table text (or given as a dict)."""
        if isinstance(options, str):
            return dict(self._texts.get((method, options), {}))
        return dict(options or {})

    def spec(self, method: str, options) -> SpecStyle:
        opts = self.options(method, options)
        base = method_style(method)
        t, fill, choice = 0.5, "full", None
        for k in self._varying.get(method, []):
            values = self._ladders.get((method, k), set())
            v = opts.get(k)
            if _numeric(v) and all(_numeric(x) for x in values):
                ordered = sorted(values)
                t = ordered.index(v) / max(1, len(ordered) - 1) if v in ordered else 0.5
            elif not _numeric(v):
                choices = self._choices.get(method, {}).get(k) or sorted(map(str, values))
                if v in choices:
                    fill = _FILLS[choices.index(v) % len(_FILLS)]
                    choice = (choices.index(v), len(choices))
        ladder = any(_numeric(opts.get(k)) for k in self._varying.get(method, []))
        family = _choice_colour(base.colour, *choice) if choice else to_rgb(base.colour)
        colour = _shade(family, t) if ladder else family
        size = 5.0 + 4.0 * t if ladder else 7.0
        if base.hollow:
            fill, size = "none", size + 3.0
        gid = f"method={method};options=" + ",".join(f"{k}={opts[k]}" for k in sorted(opts))
        return SpecStyle(method, json.dumps(opts, sort_keys=True), colour, base.marker, fill, size, base.dashes,
                         base.hollow, gid)

    def order(self, method: str, options) -> tuple:
        """Sort key of legends: method (table order), then option values (numbers by value)."""
        opts = self.options(method, options)
        names = list(METHOD_STYLES)
        rank = names.index(method) if method in names else len(names)
        values = []
        for k in self._varying.get(method, []):
            v = opts.get(k)
            if _numeric(v):
                values.append((0, float(v), ""))
            else:
                choices = self._choices.get(method, {}).get(k, [])
                values.append((1, float(choices.index(v)) if v in choices else 0.0, str(v)))
        return (rank, method, tuple(values))


def _key(method: str, opts: dict) -> str:
    return f"{method}|{json.dumps(opts, sort_keys=True)}"
