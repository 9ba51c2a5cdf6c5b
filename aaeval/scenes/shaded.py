"""Scene-format extension ``[shaded]``: Phong-shaded meshes, cylinders and cones.

A ``[shaded]`` table (``docs/shaded_scenes.md``) adds smooth-shaded objects to a scene:
triangle meshes with per-vertex normals, and cylinders and cones that aaeval tessellates
into such meshes. Each object has a Phong material and may spin a little every frame; one
directional or point light lights them all. The view is orthographic: the eye looks down
+z (smaller z is nearer) and the unit vector toward the viewer is E = (0, 0, -1).

:func:`expand_shaded` turns a scene at some frame into a plain :class:`Scene` whose
``polygons`` are the core polygons followed by every object's triangles (coloured with
the material colour, so a flat renderer draws silhouettes), and a :class:`ShadingField`
that tells a shading renderer, per polygon, the normal field and the material.
Core scenes are untouched: a scene without ``[shaded]`` expands to itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping

import numpy as np

from aaeval.scenes.format import Polygon, Scene, SceneError, number, point_list, register_section, vector

__all__ = [
    "SECTION",
    "Material",
    "Light",
    "ShadedObject",
    "ShadedSection",
    "ShadingField",
    "ShadedScene",
    "EYE",
    "tessellate_cylinder",
    "expand_shaded",
    "has_shaded",
    "rotation_matrix",
]

SECTION = "shaded"
# Facets around a cylinder or cone: far past any visible difference at the largest image
# (16384 px), and tessellated in well under a second; 1e7 took 82 s.
MAX_SEGMENTS = 65536

# unit vector from the surface toward the viewer (orthographic view down +z)
EYE = np.array([0.0, 0.0, -1.0])


@dataclass(frozen=True)
class Material:
    """Phong material: I = C (ka + kd max(N.L, 0)) + ks max(R.E, 0)^n."""

    color: np.ndarray
    ka: float
    kd: float
    ks: float
    n: float


@dataclass(frozen=True)
class Light:
    """One light: ``kind`` is ``"directional"`` (``vector`` = unit direction toward the
    light) or ``"point"`` (``vector`` = its position in image space)."""

    kind: str
    vector: np.ndarray


@dataclass(frozen=True)
class ShadedObject:
    """A triangle mesh with unit vertex normals, a material and a spin per frame."""

    vertices: np.ndarray  # (m, 3) image space
    normals: np.ndarray  # (m, 3) unit
    triangles: np.ndarray  # (t, 3) int indices
    material: Material
    pivot: np.ndarray  # (3,) centre of the spin
    spin_axis: np.ndarray  # (3,) unit
    spin_degrees: float  # per frame


@dataclass(frozen=True)
class ShadedSection:
    """The parsed ``[shaded]`` table."""

    light: Light
    objects: tuple[ShadedObject, ...]


@dataclass(frozen=True)
class ShadingField:
    """Per polygon of an expanded scene (index into ``scene.polygons``).

    ``shaded[i]`` is False for core (flat) polygons. For shaded ones the Phong normal at
    image point (x, y) is ``normalise(G[i] @ (x, y, 1))`` — the barycentric blend of the
    triangle's vertex normals, which under an orthographic view is the same blend as on
    the 3D triangle — and the material is ``color[i], ka[i], kd[i], ks[i], n[i]``.
    """

    shaded: np.ndarray  # (P,) bool
    G: np.ndarray  # (P, 3, 3)
    color: np.ndarray  # (P, 3)
    ka: np.ndarray
    kd: np.ndarray
    ks: np.ndarray
    n: np.ndarray
    planes: np.ndarray  # (P, 3) depth planes z = a x + b y + c
    light: Light | None

    def normals(self, polygon: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Unit Phong normals (k, 3) of polygons ``polygon`` at image points (x, y)."""
        g = self.G[polygon]
        v = g[:, :, 0] * x[:, None] + g[:, :, 1] * y[:, None] + g[:, :, 2]
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    def light_directions(self, polygon: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Unit vectors (k, 3) from the surface point toward the light."""
        if self.light.kind == "directional":
            return np.broadcast_to(self.light.vector, (len(x), 3))
        plane = self.planes[polygon]
        z = plane[:, 0] * x + plane[:, 1] * y + plane[:, 2]
        d = self.light.vector[None, :] - np.stack([x, y, z], axis=1)
        return d / np.linalg.norm(d, axis=1, keepdims=True)


@dataclass(frozen=True)
class ShadedScene:
    """A scene with its shaded objects expanded into triangles, and their shading data."""

    scene: Scene
    field: ShadingField


def has_shaded(scene: Scene) -> bool:
    """Whether a scene carries a ``[shaded]`` table with at least one object."""
    section = scene.extensions.get(SECTION)
    return section is not None and len(section.objects) > 0


# --- expansion ---------------------------------------------------------------------


def expand_shaded(scene: Scene) -> ShadedScene:
    """The scene's shaded objects as triangles appended to ``scene.polygons``.

    Objects are spun by ``scene.frame`` times their per-frame rotation about their
    (translated) pivot. Triangles with no area in 3D are dropped; triangles seen
    edge-on keep a NaN plane (they cover nothing, as in the core format).
    """
    section: ShadedSection | None = scene.extensions.get(SECTION)
    core = list(scene.polygons)
    n_core = len(core)
    rows: list[tuple] = []
    if section is not None:
        for obj in section.objects:
            vertices, normals = _spun(obj, scene.frame)
            v = vertices[obj.triangles]  # (t, 3, 3)
            twice_area = np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1)
            keep = twice_area > 1e-12 * (1 + np.abs(v).max()) ** 2
            rows += [(tv, tn, obj.material) for tv, tn in zip(v[keep], normals[obj.triangles[keep]])]
    planes = _triangle_planes(np.array([r[0] for r in rows]).reshape(-1, 3, 3))
    polygons = core + [
        Polygon(vertices=v, color=np.asarray(m.color, dtype=np.float64), index=n_core + i, plane=planes[i])
        for i, (v, _, m) in enumerate(rows)
    ]
    total = len(polygons)
    field = ShadingField(
        shaded=np.array([False] * n_core + [True] * len(rows), dtype=bool),
        G=_normal_fields(core, rows),
        color=np.array([p.color for p in polygons], dtype=np.float64).reshape(total, 3),
        ka=_column(rows, n_core, "ka"),
        kd=_column(rows, n_core, "kd"),
        ks=_column(rows, n_core, "ks"),
        n=_column(rows, n_core, "n"),
        planes=np.array([p.plane for p in polygons], dtype=np.float64).reshape(total, 3),
        light=None if section is None else section.light,
    )
    return ShadedScene(scene=replace(scene, polygons=tuple(polygons)), field=field)


def _triangle_planes(v: np.ndarray) -> np.ndarray:
    """Depth planes z = a x + b y + c of triangles (t, 3, 3); NaN rows for edge-on ones."""
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    size = np.ptp(v[:, :, :2], axis=1).max(axis=1) if len(v) else np.zeros(0)
    edge_on = np.abs(n[:, 2]) <= 1e-12 * np.maximum(size, 1.0) ** 2
    nz = np.where(edge_on, 1.0, n[:, 2])
    a, b = -n[:, 0] / nz, -n[:, 1] / nz
    centre = v.mean(axis=1)
    planes = np.stack([a, b, centre[:, 2] - a * centre[:, 0] - b * centre[:, 1]], axis=1)
    planes[edge_on] = np.nan
    return planes


def _column(rows, n_core: int, name: str) -> np.ndarray:
    return np.array([0.0] * n_core + [getattr(m, name) for _, _, m in rows], dtype=np.float64)


def _normal_fields(core, rows) -> np.ndarray:
    """G per polygon: vertex normals (columns) times the inverse barycentric matrix."""
    G = np.full((len(core) + len(rows), 3, 3), np.nan)
    if not rows:
        return G
    v = np.array([r[0] for r in rows])  # (t, 3, 3)
    nv = np.array([r[1] for r in rows])
    inv, det = _barycentric_inverse(v[:, :, 0], v[:, :, 1])
    ok = np.abs(det) > 1e-12 * (1 + np.abs(v[:, :, :2]).max(axis=(1, 2))) ** 2
    inv[~ok] = np.nan
    G[len(core):] = np.einsum("tvi,tvj->tij", nv, inv)  # sum over vertices v: n_v lambda_v
    return G


def _barycentric_inverse(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse and determinant of each triangle's ``T = [[x0 x1 x2], [y0 y1 y2], [1 1 1]]``.

    Row v of the inverse maps (x, y, 1) to vertex v's barycentric weight. Written out as
    cofactors over the determinant (twice the signed area) in elementwise numpy, so every CPU
    gives the same bits: LAPACK's inverse goes through OpenBLAS kernels chosen per CPU, and
    its G differed by 2e-12 between Skylake-X and Zen kernels.
    """
    x0, x1, x2 = x[:, 0], x[:, 1], x[:, 2]
    y0, y1, y2 = y[:, 0], y[:, 1], y[:, 2]
    det = (x1 * y2 - x2 * y1) - (x0 * y2 - x2 * y0) + (x0 * y1 - x1 * y0)
    cofactors = np.stack([
        np.stack([y1 - y2, x2 - x1, x1 * y2 - x2 * y1], axis=1),
        np.stack([y2 - y0, x0 - x2, x2 * y0 - x0 * y2], axis=1),
        np.stack([y0 - y1, x1 - x0, x0 * y1 - x1 * y0], axis=1),
    ], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return cofactors / det[:, None, None], det


def rotation_matrix(axis: np.ndarray, degrees: float) -> np.ndarray:
    """Rotation by ``degrees`` about the unit ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=np.float64)
    t = math.radians(degrees)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * _times_transpose(K, K.T)


def _times_transpose(points: np.ndarray, M: np.ndarray) -> np.ndarray:
    """``points @ M.T`` for rows of 3 (a point or normal per row), summed in a fixed order
    with elementwise numpy: the same bits on every CPU, where a BLAS product's order and
    fused multiply-adds depend on the kernel OpenBLAS picks for the CPU."""
    return points[:, 0:1] * M[:, 0] + points[:, 1:2] * M[:, 1] + points[:, 2:3] * M[:, 2]


def _spun(obj: ShadedObject, frame: int) -> tuple[np.ndarray, np.ndarray]:
    if frame == 0 or obj.spin_degrees == 0.0:
        return obj.vertices, obj.normals
    R = rotation_matrix(obj.spin_axis, frame * obj.spin_degrees)
    return _times_transpose(obj.vertices - obj.pivot, R) + obj.pivot, _times_transpose(obj.normals, R)


# --- tessellation ------------------------------------------------------------------


def tessellate_cylinder(
    centre, axis, radii, length: float, segments: int, *, caps: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Triangles of a cylinder or (truncated) cone with smooth side normals.

    ``radii = (r0, r1)`` are the radii at ``centre - axis * length/2`` and
    ``centre + axis * length/2``. Side vertex normals are the exact surface normals of
    the cone at that vertex; at an apex (radius 0) every triangle gets its own apex
    normal, at its mid-angle. Caps are flat fans with normal -axis / +axis.

    Returns ``(vertices (m, 3), normals (m, 3), triangles (t, 3))``.
    """
    c = np.asarray(centre, dtype=np.float64)
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    u = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(a, u)
    r0, r1 = float(radii[0]), float(radii[1])
    half = 0.5 * length
    slope = (r1 - r0) / length  # dr/ds along the axis

    def ring(theta, s, r):
        radial = np.cos(theta)[:, None] * u + np.sin(theta)[:, None] * w
        points = c + s * a + r * radial
        normal = radial - slope * a
        return points, normal / np.linalg.norm(normal, axis=1, keepdims=True)

    verts: list[np.ndarray] = []
    norms: list[np.ndarray] = []
    tris: list[tuple[int, int, int]] = []

    def add(points, normals) -> int:
        start = sum(len(p) for p in verts)
        verts.append(np.atleast_2d(points))
        norms.append(np.atleast_2d(normals))
        return start

    theta = 2 * np.pi * np.arange(segments) / segments
    mid = theta + np.pi / segments
    bottom = add(*ring(theta, -half, r0)) if r0 > 0 else add(*ring(mid, -half, 0.0))
    top = add(*ring(theta, +half, r1)) if r1 > 0 else add(*ring(mid, +half, 0.0))
    for j in range(segments):
        k = (j + 1) % segments
        if r0 > 0 and r1 > 0:
            tris += [(bottom + j, bottom + k, top + k), (bottom + j, top + k, top + j)]
        elif r1 == 0:
            tris.append((bottom + j, bottom + k, top + j))  # apex j sits at mid-angle j
        else:
            tris.append((bottom + j, top + k, top + j))
    if caps:
        for s, r, sign in ((-half, r0, -1.0), (+half, r1, +1.0)):
            if r <= 0:
                continue
            rim, _ = ring(theta, s, r)
            start = add(rim, np.tile(sign * a, (segments, 1)))
            centre_index = add(c + s * a, sign * a)
            tris += [(centre_index, start + j, start + (j + 1) % segments) for j in range(segments)]
    return np.vstack(verts), np.vstack(norms), np.array(tris, dtype=np.int64)


# --- parsing -------------------------------------------------------------------------

_OBJECT_KEYS = {
    "cylinders": {"centre", "axis", "radius", "length", "segments", "caps", "material", "spin"},
    "cones": {"centre", "axis", "radii", "length", "segments", "caps", "material", "spin"},
    "meshes": {"vertices", "normals", "triangles", "material", "spin", "pivot"},
}


def _parse(value: Any, where: str, document: dict) -> ShadedSection:
    if not isinstance(value, Mapping):
        raise SceneError(f"{where}: must be a table")
    _no_unknown(value, {"light", *_OBJECT_KEYS}, where)
    if "light" not in value:
        raise SceneError(f"{where}: missing required table 'light'")
    light = _light(value["light"], f"{where}.light")
    objects: list[ShadedObject] = []
    for kind in _OBJECT_KEYS:
        raw = value.get(kind, [])
        if not isinstance(raw, list):
            raise SceneError(f"{where}.{kind}: must be an array of tables ([[{SECTION}.{kind}]])")
        for i, item in enumerate(raw):
            objects.append(_object(kind, item, f"{where}.{kind}[{i}]"))
    return ShadedSection(light=light, objects=tuple(objects))


def _translate(section: ShadedSection, shift: np.ndarray) -> ShadedSection:
    d = np.array([shift[0], shift[1], 0.0])
    light = section.light
    if light.kind == "point":
        light = Light("point", light.vector + d)
    objects = tuple(replace(o, vertices=o.vertices + d, pivot=o.pivot + d) for o in section.objects)
    return ShadedSection(light=light, objects=objects)


def _object(kind: str, raw: Any, where: str) -> ShadedObject:
    if not isinstance(raw, Mapping):
        raise SceneError(f"{where}: must be a table")
    _no_unknown(raw, _OBJECT_KEYS[kind], where)
    _require(raw, ("material",), where)
    material = _material(raw["material"], f"{where}.material")
    if kind == "meshes":
        _require(raw, ("vertices", "normals", "triangles"), where)
        vertices = _points(raw["vertices"], f"{where}.vertices")
        normals = _unit_rows(_points(raw["normals"], f"{where}.normals"), f"{where}.normals")
        if len(normals) != len(vertices):
            raise SceneError(f"{where}: {len(normals)} normals for {len(vertices)} vertices")
        triangles = _triangles(raw["triangles"], len(vertices), f"{where}.triangles")
        pivot = vector(raw["pivot"], 3, f"{where}.pivot") if "pivot" in raw else vertices.mean(axis=0)
    else:
        _require(raw, ("centre", "axis", "length", "segments", "radii" if kind == "cones" else "radius"), where)
        centre = vector(raw["centre"], 3, f"{where}.centre")
        axis = _unit_rows(vector(raw["axis"], 3, f"{where}.axis")[None], f"{where}.axis")[0]
        length = _positive(raw["length"], f"{where}.length")
        segments = raw["segments"]
        if isinstance(segments, bool) or not isinstance(segments, int) or not 3 <= segments <= MAX_SEGMENTS:
            raise SceneError(f"{where}.segments: must be an integer in 3..{MAX_SEGMENTS}, got {segments!r}")
        if kind == "cones":
            radii = vector(raw["radii"], 2, f"{where}.radii")
            if radii.min() < 0 or radii.max() <= 0:
                raise SceneError(f"{where}.radii: need radii >= 0, not both 0, got {radii.tolist()}")
        else:
            r = _positive(raw["radius"], f"{where}.radius")
            radii = np.array([r, r])
        caps = raw.get("caps", True)
        if not isinstance(caps, bool):
            raise SceneError(f"{where}.caps: must be true or false")
        vertices, normals, triangles = tessellate_cylinder(centre, axis, radii, length, segments, caps=caps)
        pivot = centre
    spin_axis, spin_degrees = np.array([0.0, 0.0, 1.0]), 0.0
    if "spin" in raw:
        spin = raw["spin"]
        if not isinstance(spin, Mapping):
            raise SceneError(f"{where}.spin: must be a table {{axis = [x, y, z], degrees = d}}")
        _no_unknown(spin, {"axis", "degrees"}, f"{where}.spin")
        _require(spin, ("degrees",), f"{where}.spin")
        spin_degrees = number(spin["degrees"], f"{where}.spin.degrees")
        if "axis" in spin:
            spin_axis = _unit_rows(vector(spin["axis"], 3, f"{where}.spin.axis")[None], f"{where}.spin.axis")[0]
    return ShadedObject(vertices, normals, triangles, material, pivot, spin_axis, spin_degrees)


def _material(raw: Any, where: str) -> Material:
    if not isinstance(raw, Mapping):
        raise SceneError(f"{where}: must be a table {{color, ka, kd, ks, n}}")
    _no_unknown(raw, {"color", "ka", "kd", "ks", "n"}, where)
    _require(raw, ("color", "ka", "kd", "ks", "n"), where)
    coefficients = {k: number(raw[k], f"{where}.{k}") for k in ("ka", "kd", "ks")}
    for k, v in coefficients.items():
        if v < 0:
            raise SceneError(f"{where}.{k}: must be >= 0, got {v}")
    return Material(color=vector(raw["color"], 3, f"{where}.color"), n=_positive(raw["n"], f"{where}.n"), **coefficients)


def _light(raw: Any, where: str) -> Light:
    if not isinstance(raw, Mapping):
        raise SceneError(f"{where}: must be a table")
    kind = raw.get("type", "directional")
    if kind == "directional":
        _no_unknown(raw, {"type", "direction"}, where)
        _require(raw, ("direction",), where)
        return Light("directional", _unit_rows(vector(raw["direction"], 3, f"{where}.direction")[None], f"{where}.direction")[0])
    if kind == "point":
        _no_unknown(raw, {"type", "position"}, where)
        _require(raw, ("position",), where)
        return Light("point", vector(raw["position"], 3, f"{where}.position"))
    raise SceneError(f"{where}.type: must be 'directional' or 'point', got {kind!r}")


def _no_unknown(table: Mapping, allowed: set[str], where: str) -> None:
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise SceneError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def _require(table: Mapping, keys, where: str) -> None:
    for key in keys:
        if key not in table:
            raise SceneError(f"{where}: missing required key '{key}'")


def _positive(value: Any, where: str) -> float:
    v = number(value, where)
    if v <= 0:
        raise SceneError(f"{where}: must be > 0, got {v}")
    return v


def _points(value: Any, where: str) -> np.ndarray:
    if not isinstance(value, list) or not value:
        raise SceneError(f"{where}: expected a non-empty list of [x, y, z]")
    return point_list(value, where)


def _unit_rows(v: np.ndarray, where: str) -> np.ndarray:
    norm = np.linalg.norm(v, axis=1, keepdims=True)
    if (norm <= 1e-12).any():
        raise SceneError(f"{where}: zero-length direction")
    return v / norm


def _triangles(value: Any, count: int, where: str) -> np.ndarray:
    if not isinstance(value, list) or not value:
        raise SceneError(f"{where}: expected a non-empty list of [i, j, k]")
    out = []
    for i, t in enumerate(value):
        if (
            not isinstance(t, list)
            or len(t) != 3
            or any(isinstance(j, bool) or not isinstance(j, int) or not 0 <= j < count for j in t)
        ):
            raise SceneError(f"{where}[{i}]: expected 3 vertex indices in 0..{count - 1}, got {t!r}")
        out.append(t)
    return np.array(out, dtype=np.int64)


register_section(SECTION, _parse, _translate)
