"""The polygon scene format (``docs/scene_format.md``): the scene, its polygons and their rules.

A scene file is TOML. Its core keys are ``[image]``, ``[animation]`` and
``[[polygons]]``; other top-level tables are extensions, each parsed by a function
registered with :func:`register_section`. This module holds the :class:`Scene`, the
polygon and its checks; :mod:`aaeval.scenes.document` reads a whole document with them
(and with :mod:`aaeval.scenes.holes`, which builds on them). Every rule is checked before
anything is rendered, and a broken file raises :class:`SceneError` naming the file, the
polygon and the rule.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from fractions import Fraction
from functools import cached_property
from typing import Any, Callable, Mapping

import numpy as np

from aaeval._toml import refuse_unknown_keys
from aaeval.options import Registry
from aaeval.scenes.simplicity import ring_contact

__all__ = [
    "Polygon",
    "PolygonArrays",
    "Scene",
    "SceneError",
    "register_section",
    "SECTIONS",
    "Section",
]

# Relative tolerance for "planar": distance of a vertex from the best-fit plane,
# against the polygon's size. Well above float64 noise, far below any visible tilt.
PLANARITY_RTOL = 1e-9
# Beyond these, float64 pixel coordinates lose the precision exact area sampling needs.
MAX_COORDINATE = 1e9
MAX_PIXELS = 1 << 28


class SceneError(ValueError):
    """A scene file (or dictionary) breaks a rule of the scene format."""


@dataclass(frozen=True)
class Polygon:
    """One flat-coloured planar polygon in image space.

    Attributes
    ----------
    vertices : ndarray, shape (n, 3)
        x, y (pixels, y down) and depth z, in the file's order.
    color : ndarray, shape (3,)
        Linear RGB.
    index : int
        Position in ``Scene.polygons``: the file's order, where a polygon with holes
        stands as its abutting pieces in a row (:mod:`aaeval.scenes.holes`); on an exactly
        shared depth plane the later one is in front.
    plane : ndarray, shape (3,)
        ``(a, b, c)`` with depth ``z = a x + b y + c``; NaN for a polygon seen edge-on
        (zero projected area), which covers nothing.
    """

    vertices: np.ndarray
    color: np.ndarray
    index: int
    plane: np.ndarray

    @property
    def xy(self) -> np.ndarray:
        return self.vertices[:, :2]


@dataclass(frozen=True)
class PolygonArrays:
    """Every polygon of a scene in flat arrays, for vectorised code and kernels.

    Polygon ``i`` is ``vertices[start[i] : start[i] + length[i]]``.
    """

    vertices: np.ndarray  # (N, 3)
    start: np.ndarray  # (P,) int64
    length: np.ndarray  # (P,) int64
    colors: np.ndarray  # (P, 3)
    planes: np.ndarray  # (P, 3), NaN rows for polygons seen edge-on

    @classmethod
    def of(cls, polygons) -> "PolygonArrays":
        length = np.array([len(p.vertices) for p in polygons], dtype=np.int64)
        start = np.zeros(len(polygons), dtype=np.int64)
        start[1:] = np.cumsum(length)[:-1]
        return cls(
            vertices=np.concatenate([p.vertices for p in polygons]) if polygons else np.zeros((0, 3)),
            start=start,
            length=length,
            colors=np.array([p.color for p in polygons], dtype=np.float64).reshape(-1, 3),
            planes=np.array([p.plane for p in polygons], dtype=np.float64).reshape(-1, 3),
        )


@dataclass(frozen=True)
class Scene:
    """A parsed, validated scene at one frame of its animation."""

    width: int
    height: int
    background: np.ndarray
    polygons: tuple[Polygon, ...]
    frames: int = 1
    translate: np.ndarray = field(default_factory=lambda: np.zeros(2))
    frame: int = 0
    source: str = "<scene>"
    extensions: Mapping[str, Any] = field(default_factory=dict)
    # the file's polygons with holes; each is already in ``polygons`` as abutting pieces
    holed: tuple = ()  # of aaeval.scenes.holes.HoledPolygon
    # sub-pixel offsets added to the drift (aaeval.scenes.phases); "none" moves as before
    phases: str = "none"
    phase_seed: int = 0

    def offset(self, k: int) -> np.ndarray:
        """Where frame ``k`` is moved to, relative to the scene as written (px, (2,))."""
        from aaeval.scenes.phases import phase_offset

        if self.phases == "none":  # the shipped motion, bit for bit: no offset added
            return int(k) * self.translate
        return int(k) * self.translate + phase_offset(self.phases, int(k), self.phase_seed)

    @cached_property
    def arrays(self) -> PolygonArrays:
        """The polygons as flat arrays (built once per scene object)."""
        return PolygonArrays.of(self.polygons)

    def at_frame(self, k: int) -> "Scene":
        """The scene translated to frame ``k`` (0-based) of its animation."""
        if not (isinstance(k, (int, np.integer)) and 0 <= k < self.frames):
            raise SceneError(f"{self.source}: frame {k} is outside 0..{self.frames - 1}")
        shift = (int(k) - self.frame) * self.translate if self.phases == "none" else \
            self.offset(int(k)) - self.offset(self.frame)
        if not shift.any():
            return replace(self, frame=int(k))
        return self._shifted(shift, frame=int(k))

    def window(self, x0: int, y0: int, width: int, height: int) -> "Scene":
        """The scene seen through the pixel window of columns ``x0 .. x0 + width - 1`` and
        rows ``y0 .. y0 + height - 1``: everything moved by ``(-x0, -y0)`` (polygons, holes
        and every section, point lights and spin pivots included) in an image of
        ``width x height``, at every frame of the animation.

        A box-filtered pixel depends only on what covers its own square, so rendering the
        window gives the full render's crop ``[y0 : y0 + height, x0 : x0 + width]`` (up to
        rounding of the moved coordinates) for the cost of the window: a figure that shows a
        small part of a large scene renders only that part.
        """
        for name, value in (("x0", x0), ("y0", y0), ("width", width), ("height", height)):
            if not isinstance(value, (int, np.integer)) or isinstance(value, bool):
                raise SceneError(f"{self.source}: window {name} must be an integer, got {value!r}")
        if not (0 <= x0 and 0 <= y0 and 0 < width and 0 < height
                and x0 + width <= self.width and y0 + height <= self.height):
            raise SceneError(f"{self.source}: window {width}x{height} at ({x0}, {y0}) is not inside "
                             f"the {self.width}x{self.height} image")
        moved = self._shifted(np.array([-float(x0), -float(y0)]), frame=self.frame)
        return replace(moved, width=int(width), height=int(height),
                       source=f"{self.source} (window {width}x{height} at {x0}, {y0})")

    def _shifted(self, shift: np.ndarray, frame: int) -> "Scene":
        """The scene with everything moved by ``shift`` (px, (2,)), at ``frame``."""
        arrays = _translated(self.arrays, shift)
        moved = tuple(
            Polygon(vertices=arrays.vertices[s : s + n], color=p.color, index=p.index, plane=arrays.planes[i])
            for i, (p, s, n) in enumerate(zip(self.polygons, arrays.start, arrays.length))
        )
        extensions = {
            name: SECTIONS[name].translate(value, shift) if SECTIONS[name].translate else value
            for name, value in self.extensions.items()
        }
        holed = tuple(h.translated(shift) for h in self.holed)
        scene = replace(self, polygons=moved, frame=frame, extensions=extensions, holed=holed)
        scene.__dict__["arrays"] = arrays  # already known: spare rebuilding it
        return scene

    @property
    def shape(self) -> tuple[int, int, int]:
        return (self.height, self.width, 3)

    def __repr__(self) -> str:
        """One short line (the dataclass repr would print every vertex): source, size,
        polygon count, frames, sections."""
        source = self.source if len(self.source) <= 100 else "..." + self.source[-97:]
        sections = ", ".join(sorted(self.extensions))
        extras = f", sections: {sections if len(sections) <= 60 else sections[:57] + '...'}" if sections else ""
        frames = f", frame {self.frame} of {self.frames}" if self.frames > 1 else ""
        return f"Scene({source!r}, {self.width}x{self.height}, {len(self.polygons)} polygons{frames}{extras})"


def _translated(arrays: PolygonArrays, shift: np.ndarray) -> PolygonArrays:
    vertices = arrays.vertices.copy()
    vertices[:, :2] += shift
    planes = arrays.planes.copy()
    # z = a x + b y + c moved by (dx, dy): the same a, b with c - a dx - b dy
    planes[:, 2] -= planes[:, 0] * shift[0] + planes[:, 1] * shift[1]
    return replace(arrays, vertices=vertices, planes=planes)


@dataclass(frozen=True)
class Section:
    """A registered extension table: ``parse(value, where, document)`` and ``translate(parsed, shift)``."""

    parse: Callable[[Any, str, dict], Any]
    translate: Callable[[Any, np.ndarray], Any] | None


#: The extension tables of the scene format, by top-level key (:func:`register_section`).
SECTIONS: Registry = Registry("scene section")
CORE_KEYS = {"image", "animation", "polygons"}


def register_section(
    name: str,
    parse: Callable[[Any, str, dict], Any] | None = None,
    translate: Callable[[Any, np.ndarray], Any] | None = None,
):
    """Register an extension table of the scene format: ``register_section(name, parse,
    translate)`` or ``@register_section(name, translate=...)`` over ``parse``; a name
    registered twice is refused.

    ``parse(value, where, document)`` validates the raw TOML value (raising
    :class:`SceneError` with ``where`` in the message) and returns what renderers read
    from ``scene.extensions[name]``; ``translate(parsed, shift)`` moves it by a frame's
    translation.
    """
    if name in CORE_KEYS:
        raise ValueError(f"{name!r} is a core key of the scene format")

    def decorate(func):
        SECTIONS.add(name, Section(func, translate))
        return func

    return decorate if parse is None else decorate(parse)


# --- checks -----------------------------------------------------------------------


def no_unknown(table: Mapping, allowed: set[str], where: str) -> None:
    """Refuse, naming ``where``, any key of ``table`` not in ``allowed``."""
    refuse_unknown_keys(table, allowed, where, SceneError)


def number(value: Any, where: str) -> float:
    """A finite TOML number (not a boolean) as float; SceneError naming ``where`` else."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(f"{where}: expected a number, got {value!r}")
    if not math.isfinite(value):
        raise SceneError(f"{where}: non-finite number {value!r}")
    return float(value)


def vector(value: Any, n: int, where: str) -> np.ndarray:
    """A list of ``n`` finite numbers as a float64 array (see :func:`number`)."""
    if not isinstance(value, list) or len(value) != n:
        raise SceneError(f"{where}: expected a list of {n} numbers, got {value!r}")
    return np.array([number(v, where) for v in value], dtype=np.float64)


def rgb(value: Any, where: str) -> np.ndarray:
    """A linear RGB colour: three numbers in [0, 1]."""
    colour = vector(value, 3, where)
    if np.any((colour < 0.0) | (colour > 1.0)):
        raise SceneError(f"{where}: colour components must be in [0, 1] (linear RGB), got {value!r}")
    return colour


def parse_polygon(raw: Any, i: int, source: str) -> Polygon:
    """Polygon ``i`` of ``source`` from its raw table, every rule of its outer ring checked."""
    where = f"{source}: polygons[{i}]"
    if not isinstance(raw, Mapping):
        raise SceneError(f"{where}: must be a table with 'color' and 'vertices'")
    no_unknown(raw, {"color", "vertices", "holes"}, where)
    for key in ("color", "vertices"):
        if key not in raw:
            raise SceneError(f"{where}: missing required key '{key}'")
    color = rgb(raw["color"], f"{where}.color")
    vertices_raw = raw["vertices"]
    if not isinstance(vertices_raw, list):
        raise SceneError(f"{where}.vertices: expected a list of [x, y, z] points")
    if len(vertices_raw) < 3:
        raise SceneError(f"{where}: a polygon needs at least 3 vertices, got {len(vertices_raw)}")
    vertices = point_list(vertices_raw, f"{where}.vertices")
    if np.abs(vertices).max() > MAX_COORDINATE:
        raise SceneError(f"{where}: coordinates beyond +-{MAX_COORDINATE:g} are not supported")
    check_no_repeats(vertices, where)
    in_plane = check_planar(vertices, where)
    check_simple(in_plane, where)
    return Polygon(vertices=vertices, color=color, index=i, plane=_plane_of(vertices))


def point_list(raw: list, where: str) -> np.ndarray:
    """The ``(n, 3)`` float64 array of a list of ``[x, y, z]`` points, each checked as
    :func:`vector` checks it (the error names ``where[j]``, the first bad point).

    Well-formed lists (plain lists of three finite ints or floats, as TOML gives them) are
    converted in one call; only a list that fails that test goes point by point, to find
    the point to name. An imported glyph or map has thousands of polygons: one small array
    per point was most of the time spent reading them.
    """
    if all(type(p) is list and len(p) == 3 for p in raw) and {type(c) for p in raw for c in p} <= {float, int}:
        try:
            points = np.array(raw, dtype=np.float64)
        except OverflowError:  # an int beyond float64: the point-by-point path says which
            points = None
        if points is not None and np.isfinite(points).all():
            return points
    return np.array([vector(p, 3, f"{where}[{j}]") for j, p in enumerate(raw)])


def next_vertices(ring: np.ndarray) -> np.ndarray:
    """Each vertex's successor around a ring: ``np.roll(ring, -1, axis=0)`` without its
    argument handling, which cost more than the arithmetic on a glyph's small rings."""
    return np.concatenate((ring[1:], ring[:1]))


def newell_normal(vertices: np.ndarray) -> np.ndarray:
    """Newell's normal of a polygon: twice its vector area, robust for concave outlines."""
    v = vertices - vertices.mean(axis=0)
    nxt = next_vertices(v)
    d, s = v - nxt, v + nxt
    return np.array(
        [
            np.sum(d[:, 1] * s[:, 2]),
            np.sum(d[:, 2] * s[:, 0]),
            np.sum(d[:, 0] * s[:, 1]),
        ]
    )


def _plane_of(vertices: np.ndarray) -> np.ndarray:
    """Depth plane ``z = a x + b y + c``; NaN when the polygon is seen edge-on."""
    n = newell_normal(vertices)
    size = (vertices[:, :2].max(axis=0) - vertices[:, :2].min(axis=0)).max() if len(vertices) else 0.0
    if abs(n[2]) <= 1e-12 * max(size, 1.0) ** 2:
        return np.full(3, np.nan)
    centre = vertices.mean(axis=0)
    a, b = -n[0] / n[2], -n[1] / n[2]
    return np.array([a, b, centre[2] - a * centre[0] - b * centre[1]])


def check_no_repeats(vertices: np.ndarray, where: str) -> None:
    """Refuse a ring with a vertex equal to the next one (a zero-length edge)."""
    same = np.all(vertices == next_vertices(vertices), axis=1)
    if same.any():
        j = int(np.flatnonzero(same)[0])
        k = (j + 1) % len(vertices)
        hint = " (the outline closes by itself: leave out the closing vertex)" if k == 0 else ""
        raise SceneError(f"{where}: vertex {k} repeats vertex {j} (zero-length edge){hint}")


def check_planar(vertices: np.ndarray, where: str) -> np.ndarray:
    """Refuse a degenerate or non-planar outline; return it in its own plane's 2-D coordinates.

    The plane is the best fit by singular value decomposition, which (unlike Newell's
    normal) stays defined for an outline whose signed areas cancel, such as a bow tie.
    """
    centred = vertices - vertices.mean(axis=0)
    _, sing, axes = np.linalg.svd(centred, full_matrices=False)
    size = (vertices.max(axis=0) - vertices.min(axis=0)).max()
    if size == 0.0 or sing[1] <= 1e-12 * sing[0]:
        if _collinear_exactly(vertices):
            raise SceneError(f"{where}: degenerate polygon (all vertices on one line or point)")
        # a valid sliver thinner than the fit can resolve (area ~1e-16): kept, it covers
        # (nearly) nothing, and its plane is undefined like an edge-on polygon's
        return centred @ axes[:2].T
    if len(vertices) > 3:
        distance = np.abs(centred @ axes[2])
        if distance.max() > PLANARITY_RTOL * size:
            j = int(distance.argmax())
            raise SceneError(
                f"{where}: polygon is not planar (vertex {j} lies {distance.max():.3g} "
                "from the plane of the others)"
            )
    return centred @ axes[:2].T


def _collinear_exactly(vertices: np.ndarray) -> bool:
    """Whether every vertex lies exactly on one line (or point), in exact rational
    arithmetic: only asked of outlines whose fitted thickness is below rounding."""
    points = [[Fraction(c) for c in row] for row in vertices.tolist()]
    origin = points[0]
    far = points[int(np.abs(vertices - vertices[0]).sum(axis=1).argmax())]
    d = [b - a for a, b in zip(origin, far)]
    for q in points:
        e = [b - a for a, b in zip(origin, q)]
        if d[1] * e[2] != d[2] * e[1] or d[2] * e[0] != d[0] * e[2] or d[0] * e[1] != d[1] * e[0]:
            return False
    return True


def check_simple(xy: np.ndarray, where: str) -> None:
    """Refuse an outline whose non-adjacent edges cross or touch (in its own plane).

    O(n log n) (a sweep line beyond a few hundred edges): a 100000-vertex outline is
    checked in about a second.
    """
    if len(xy) < 4:
        return
    hit = ring_contact(xy)
    if hit is not None:
        raise SceneError(f"{where}: polygon is self-crossing (edge {hit[0]} meets edge {hit[1]})")
