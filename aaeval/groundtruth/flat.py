"""The flat-colour ground truth: an aaeval scene rendered by Mitsuba 3.

The conversion is split into small public steps so the Phong ground truth
(:mod:`aaeval.groundtruth.phong`) reuses them:

- :func:`triangulate_scene`: every visible polygon, clipped to a margin around the image
  and ear-cut into triangles (concave outlines included), with camera depths;
- :func:`camera_depths`: scene z to camera depth, monotone, with a file-order nudge for
  polygons on one shared plane (the later one in front, as the scene format says);
- :func:`scene_mesh`: one Mitsuba mesh of all triangles plus a background quad, with a
  per-face ``face_color`` attribute;
- :func:`orthographic_sensor`: the camera that maps pixel (col i, row j) onto world
  [i, i+1] x [j, j+1], box pixel filter, float32 ``hdrfilm``;
- :func:`mitsuba_scene_dict`: all of it as a ``mi.load_dict`` dictionary;
- :func:`render_in_bands`: large films rendered in row bands, one seed each;
- :func:`render_mitsuba`: the (H, W, 3) float64 image, row 0 at the top (not cached:
  :mod:`aaeval.groundtruth.cache` caches it).

Mitsuba computes in float32. Vertices are clipped to at most :data:`MARGIN` pixels
outside the image so far-away vertices cannot cost precision, and scene depths are mapped
affinely onto [:data:`NEAR`, :data:`NEAR` + :data:`DEPTH_SPAN`] in front of the camera,
which keeps visibility and every interpenetration line (an affine map of z preserves
planes and where they cross).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from aaeval.native import catmull as _catmull
from aaeval.mitsuba_variant import import_mitsuba
from aaeval.scenes import Scene
from aaeval.scenes.depth import depth_tolerance
from aaeval.scenes.holes import ring_area
from aaeval.weiler_atherton.near_ties import resolve_flat_arrays

__all__ = [
    "SAMPLERS",
    "DEFAULT_SAMPLER",
    "DEFAULT_SPP",
    "MARGIN",
    "NEAR",
    "DEPTH_SPAN",
    "COPLANAR_NUDGE",
    "Triangles",
    "clip_to_window",
    "coplanar_ranks",
    "camera_depths",
    "triangulate_scene",
    "scene_mesh",
    "orthographic_sensor",
    "mitsuba_scene_dict",
    "render_mitsuba",
    "render_in_bands",
    "MAX_SAMPLES_PER_PASS",
    "row_bands",
    "band_seed",
]

# Mitsuba samplers that keep each sample inside its pixel with the box filter and make
# sense for a converging ground truth (stratified and multijitter round spp up to a square).
SAMPLERS = ("stratified", "independent", "multijitter", "ldsampler")
# Measured on the shipped scenes (benchmarks/mitsuba_convergence.py, 3 seeds): stratified
# at 4096 spp leaves 5 of 16 above RMSE 2e-4 against the exact image (slivers 5.4e-4,
# picket fence 7.5e-4), multijitter at 4096 leaves 3; multijitter at 16384 keeps every
# one below 1.3e-4 at under 0.5 s for 32x32.
DEFAULT_SAMPLER = "multijitter"
DEFAULT_SPP = 16384

MARGIN = 1.0  # pixels kept around the image when clipping
NEAR = 1.0  # camera depth of the nearest polygon
DEPTH_SPAN = 100.0  # camera depths of the polygons span [NEAR, NEAR + DEPTH_SPAN]
# Camera-depth step between polygons on one shared plane. Float32 hit distances near
# NEAR + DEPTH_SPAN are resolved to ~1e-5; the step is 100 times that, so the later
# polygon wins every tie, and it is 1e-5 of the depth span, so it moves a line where such
# a polygon crosses another one by 1e-5 / (their depth-slope difference in span units).
COPLANAR_NUDGE = 1e-3
# The smallest depth range mapped onto the span, in tie bands (eps): differences of a few
# eps then land 1e-4 of the span apart, below float32's resolution, so ties are the
# nudge's to decide, as coplanar_ranks says.
TIE_SPAN = 1e6
# Samples Mitsuba traces in one kernel launch; larger renders are split into row bands.
MAX_SAMPLES_PER_PASS = 1 << 28


class Triangles(NamedTuple):
    """The scene as triangles in camera space.

    ``vertices`` (n, 3) float64: x, y in pixels (y down) and camera depth (> 0, larger is
    farther); ``faces`` (m, 3) int: vertex indices; ``polygon`` (m,) int: index into
    ``scene.polygons`` of each face's polygon.
    """

    vertices: np.ndarray
    faces: np.ndarray
    polygon: np.ndarray


def clip_to_window(xy: np.ndarray, window: tuple[float, float, float, float]) -> np.ndarray:
    """The part of a polygon outline inside an axis-aligned window ``(x0, y0, x1, y1)``.

    Sutherland-Hodgman clipping (Catmull's clipper, ``src/common/geometry.hpp``) against
    the four sides; a concave polygon may come back with zero-width bridges along the
    window's border, which cover no area. Returns an (k, 2) array, k == 0 when nothing is
    inside.
    """
    x0, y0, x1, y1 = window
    if xy[:, 0].min() >= x0 and xy[:, 0].max() <= x1 and xy[:, 1].min() >= y0 and xy[:, 1].max() <= y1:
        return xy
    return _catmull.clip_to_window(np.ascontiguousarray(xy[:, 0], dtype=np.float64),
                                   np.ascontiguousarray(xy[:, 1], dtype=np.float64), *map(float, window))


def coplanar_ranks(scene: Scene, *, rtol: float = 1e-11) -> np.ndarray:
    """Depth order by file position among polygons that overlap on one shared plane.

    ``rank[j] = 1 + max(rank[i])`` over earlier polygons ``i`` on exactly ``j``'s depth
    plane whose bounding boxes overlap ``j``'s (0 if there are none), so every later
    polygon of an overlapping pair ranks higher, and ranks stay as small as the stacks of
    overlapping polygons are deep (each rank costs a nudge, :func:`camera_depths`).
    Two planes count as one when their depths agree within ``rtol * (1 + max |z|)`` at
    three corners of the image (the tolerance ``catmull`` uses for a shared plane).
    Edge-on polygons (NaN plane) get rank 0.
    """
    arrays = scene.arrays
    corners = np.array([[0.0, 0.0, 1.0], [scene.width, 0.0, 1.0], [0.0, scene.height, 1.0]])
    depth = arrays.planes @ corners.T  # (n, 3): depth of each plane at the corners
    eps = rtol * (1.0 + np.abs(arrays.vertices[:, 2]).max(initial=0.0))
    ranks = np.zeros(len(depth), dtype=np.int64)
    if len(depth) < 2:
        return ranks
    xy = arrays.vertices[:, :2]
    lo, hi = np.minimum.reduceat(xy, arrays.start), np.maximum.reduceat(xy, arrays.start)
    group = np.arange(len(depth))
    for h in scene.holed:  # a polygon with holes ranks as one: its pieces share plane, box, rank
        group[h.pieces] = h.first
        lo[h.pieces], hi[h.pieces] = lo[h.pieces].min(axis=0), hi[h.pieces].max(axis=0)
    for j in range(1, len(depth)):
        below = np.all(np.abs(depth[:j] - depth[j]) <= eps, axis=1) & (group[:j] != group[j])
        below &= np.all((lo[:j] <= hi[j]) & (hi[:j] >= lo[j]), axis=1)
        if below.any():
            ranks[j] = 1 + ranks[:j][below].max()
    return ranks


def camera_depths(z: np.ndarray, zmin: float, zmax: float, rank: np.ndarray | int = 0) -> np.ndarray:
    """Scene depths ``z`` mapped affinely onto camera depths, nearest ``NEAR``.

    ``[zmin, zmax]`` goes to ``[NEAR, NEAR + DEPTH_SPAN]`` (a single depth to the middle);
    then each point moves ``rank * COPLANAR_NUDGE`` towards the camera (see
    :func:`coplanar_ranks`). The camera's near clip (0.01) leaves room for stacks of 990
    overlapping polygons on one plane; deeper ones raise ``ValueError``.
    """
    if np.max(rank, initial=0) * COPLANAR_NUDGE >= NEAR - 0.01:
        raise ValueError("more than 990 overlapping polygons share one depth plane; the mitsuba ground truth cannot order them")
    z = np.asarray(z, dtype=np.float64)
    if zmax > zmin:
        depth = NEAR + (z - zmin) * (DEPTH_SPAN / (zmax - zmin))
    else:
        depth = np.full_like(z, NEAR + DEPTH_SPAN / 2)
    return depth - np.asarray(rank) * COPLANAR_NUDGE


def triangulate_scene(scene: Scene, *, margin: float = MARGIN) -> Triangles:
    """Every polygon that can be seen, clipped to the image plus ``margin`` and ear-cut.

    Depth of a clipped vertex is the polygon's own plane at that point, so clipping never
    bends a polygon. Polygons seen edge-on (NaN plane) cover nothing and are left out.
    """
    import mapbox_earcut

    window = (-margin, -margin, scene.width + margin, scene.height + margin)
    ranks = coplanar_ranks(scene)
    pieces = []  # (xy, z, rank, polygon index)
    for outline, plane, index in _outlines_by_tie_rule(scene):
        xy = clip_to_window(outline, window)
        if len(xy) < 3:
            continue
        a, b, c = plane
        pieces.append((xy, a * xy[:, 0] + b * xy[:, 1] + c, ranks[index], index))
    if not pieces:
        return Triangles(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64))
    zmin = min(z.min() for _, z, _, _ in pieces)
    # depths within the tie band are one depth: a scene whose depths all lie within a few
    # eps must not have them stretched over the whole span, past the coplanar nudge
    zmax = max(max(z.max() for _, z, _, _ in pieces), zmin + TIE_SPAN * depth_tolerance(scene.arrays.vertices[:, 2]))
    vertices, faces, owner, offset = [], [], [], 0
    for xy, z, rank, index in pieces:
        tri = mapbox_earcut.triangulate_float64(xy, np.array([len(xy)], dtype=np.uint32)).reshape(-1, 3)
        vertices.append(np.column_stack([xy, camera_depths(z, zmin, zmax, rank)]))
        faces.append(tri.astype(np.int64) + offset)
        owner.append(np.full(len(tri), index, dtype=np.int64))
        offset += len(xy)
    return Triangles(np.concatenate(vertices), np.concatenate(faces), np.concatenate(owner))


def _outlines_by_tie_rule(scene: Scene):
    """(outline (k, 2), plane, polygon index) of every polygon not seen edge-on, with each
    group of nearly coplanar polygons replaced by its visible regions under the scene
    format's tie rule (:mod:`aaeval.weiler_atherton.near_ties`): float32 ray tracing cannot
    tell depths 1e-11 apart, so such groups are resolved before Mitsuba sees them (pairs
    tied over their whole overlap are ranked by :func:`coplanar_ranks`)."""
    drawable = [p for p in scene.polygons if np.isfinite(p.plane).all()]
    if not drawable:
        return []
    outlines = [p.xy if ring_area(p.xy) >= 0 else p.xy[::-1] for p in drawable]
    length = np.array([len(o) for o in outlines], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(length)[:-1]]).astype(np.int64)
    xy = np.concatenate(outlines)
    planes = np.array([p.plane for p in drawable], dtype=np.float64)
    source = np.array([p.index for p in drawable], dtype=np.int64)
    start, length, x, y, planes, source = resolve_flat_arrays(
        start, length, np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), planes, source,
        depth_tolerance(scene.arrays.vertices[:, 2]))
    return [(np.column_stack([x[s:s + n], y[s:s + n]]), planes[k], int(source[k]))
            for k, (s, n) in enumerate(zip(start, length))]


def _background_quad(scene: Scene, margin: float) -> tuple[np.ndarray, np.ndarray]:
    x0, y0, x1, y1 = -margin, -margin, scene.width + margin, scene.height + margin
    depth = NEAR + DEPTH_SPAN + 1.0  # behind every polygon
    vertices = np.array([[x0, y0, depth], [x1, y0, depth], [x1, y1, depth], [x0, y1, depth]])
    return vertices, np.array([[0, 1, 2], [0, 2, 3]])


def scene_mesh(scene: Scene, triangles: Triangles | None = None, *, bsdf: dict | None = None, name: str = "polygons"):
    """One Mitsuba mesh of the scene's triangles and a background quad behind them.

    Each face carries the attribute ``face_color`` (its polygon's colour, the background
    colour for the quad), read by the default BSDF ``diffuse`` with a ``mesh_attribute``
    reflectance; pass ``bsdf`` (a ``load_dict`` dictionary) to shade differently. Needs
    a variant already set (:func:`~aaeval.mitsuba_variant.import_mitsuba`).
    """
    import mitsuba as mi

    triangles = triangulate_scene(scene) if triangles is None else triangles
    bg_vertices, bg_faces = _background_quad(scene, MARGIN)
    vertices = np.concatenate([triangles.vertices, bg_vertices])
    faces = np.concatenate([triangles.faces, bg_faces + len(triangles.vertices)])
    face_colors = np.concatenate([scene.arrays.colors[triangles.polygon], np.tile(scene.background, (2, 1))])

    props = mi.Properties()
    props["bsdf"] = mi.load_dict(
        bsdf or {"type": "diffuse", "reflectance": {"type": "mesh_attribute", "name": "face_color"}}
    )
    mesh = mi.Mesh(name, len(vertices), len(faces), props)
    params = mi.traverse(mesh)
    params["vertex_positions"] = np.ascontiguousarray(vertices, dtype=np.float32).ravel()
    params["faces"] = np.ascontiguousarray(faces, dtype=np.uint32).ravel()
    params.update()
    mesh.add_attribute("face_color", 3, np.ascontiguousarray(face_colors, dtype=np.float32).ravel())
    return mesh


def orthographic_sensor(
    width: int,
    height: int,
    *,
    sampler: str = DEFAULT_SAMPLER,
    spp: int = DEFAULT_SPP,
    rows: tuple[int, int] | None = None,
    rfilter: dict | None = None,
) -> dict:
    """The ``load_dict`` dictionary of a camera showing pixel (col i, row j) as world [i, i+1] x [j, j+1].

    Orthographic, looking along +z from depth 0 with y down (``up = -y``); Mitsuba's
    orthographic camera spans 2 world units across the film's width and keeps the pixel
    aspect, so x and y are both scaled by ``width / 2`` (also when width != height).
    Box pixel filter unless ``rfilter`` (an ``rfilter`` dictionary, see
    :data:`aaeval.filters.FILTERS`) says otherwise; float32 RGB ``hdrfilm``.
    ``rows = (r0, r1)`` renders only rows r0..r1-1 (a crop of the same film).
    """
    import mitsuba as mi

    T = mi.ScalarTransform4f
    to_world = T().look_at(
        origin=[width / 2, height / 2, 0.0], target=[width / 2, height / 2, 1.0], up=[0.0, -1.0, 0.0]
    ) @ T().scale([width / 2, width / 2, 1.0])
    film = {
        "type": "hdrfilm",
        "width": width,
        "height": height,
        "rfilter": dict(rfilter or {"type": "box"}),
        "pixel_format": "rgb",
        "component_format": "float32",
    }
    if rows is not None:
        film.update(crop_offset_x=0, crop_offset_y=rows[0], crop_width=width, crop_height=rows[1] - rows[0])
    return {
        "type": "orthographic",
        "to_world": to_world,
        "near_clip": 0.01,
        "far_clip": 2 * (NEAR + DEPTH_SPAN) + 10.0,
        "film": film,
        "sampler": {"type": sampler, "sample_count": spp},
    }


def mitsuba_scene_dict(
    scene: Scene,
    *,
    spp: int = DEFAULT_SPP,
    sampler: str = DEFAULT_SAMPLER,
    integrator: dict | None = None,
    mesh=None,
    rows: tuple[int, int] | None = None,
    rfilter: dict | None = None,
) -> dict:
    """The whole scene as a ``mi.load_dict`` dictionary (variant must be set).

    The default integrator is ``aov`` with the ``albedo`` of the diffuse BSDF, i.e. the
    flat colour at the first hit, with no lighting and no facing test.
    """
    return {
        "type": "scene",
        "integrator": integrator or {"type": "aov", "aovs": "albedo:albedo"},
        "sensor": orthographic_sensor(scene.width, scene.height, sampler=sampler, spp=spp, rows=rows, rfilter=rfilter),
        "polygons": scene_mesh(scene) if mesh is None else mesh,
    }


def row_bands(width: int, height: int, spp: int, max_samples: int | None = None) -> list[tuple[int, int]]:
    """Equal row bands with at most ``max_samples`` (default :data:`MAX_SAMPLES_PER_PASS`) samples each."""
    max_samples = MAX_SAMPLES_PER_PASS if max_samples is None else max_samples
    rows_per_band = max(1, min(height, max_samples // max(1, width * spp)))
    n = -(-height // rows_per_band)
    rows_per_band = -(-height // n)
    return [(r, min(height, r + rows_per_band)) for r in range(0, height, rows_per_band)]


def band_seed(seed: int, band: int) -> int:
    """Seed of row band ``band``; band 0 uses ``seed`` itself."""
    return (seed + band * 2654435761) % (1 << 32)


def render_mitsuba(
    scene: Scene,
    *,
    spp: int = DEFAULT_SPP,
    sampler: str = DEFAULT_SAMPLER,
    seed: int = 0,
    variant: str = "auto",
    rfilter: dict | None = None,
) -> np.ndarray:
    """Render ``scene`` with Mitsuba: (H, W, 3) float64 linear RGB, row 0 at the top.

    Each pixel is the mean of ``spp`` samples of the flat colour visible at a point of
    the pixel square (box filter), so the image converges to the exact area average that
    ``catmull`` computes. With ``rfilter`` (a wider filter) the film weights each sample
    by the filter of every pixel it reaches and divides by the weight collected, and the
    image is rendered in one pass (row bands would cut the filter at their edges).
    Core polygon scenes only: a scene with extension tables raises ``ValueError``, since
    this renderer would silently ignore them.
    """
    from aaeval.scenes.sources import SOURCE_TABLES  # where imported polygons came from: nothing to draw

    if set(scene.extensions) - SOURCE_TABLES:
        raise ValueError(
            f"{scene.source}: the mitsuba ground truth renders core polygon scenes only; "
            f"extension table(s) {sorted(set(scene.extensions) - SOURCE_TABLES)} are not supported"
        )
    if sampler not in SAMPLERS:
        raise ValueError(f"unknown sampler {sampler!r}; use one of {', '.join(SAMPLERS)}")
    mi = import_mitsuba(variant)
    mesh = scene_mesh(scene)
    out = render_in_bands(
        mi, scene, spp=spp, seed=seed, whole=rfilter is not None,
        scene_dict=lambda rows: mitsuba_scene_dict(scene, spp=spp, sampler=sampler, mesh=mesh, rows=rows,
                                                   rfilter=rfilter),
    )
    return out[..., :3]


def render_in_bands(mi, scene: Scene, *, spp: int, seed: int, scene_dict, whole: bool = False) -> np.ndarray:
    """Render the whole film in row bands (:func:`row_bands`), each with its own seed.

    ``whole=True`` renders one pass: a filter wider than a pixel would be cut at band edges.

    ``scene_dict(rows)`` gives the ``load_dict`` dictionary of rows ``(r0, r1)`` (None for
    the whole film). Returns every film channel, (H, W, C) float64.
    """
    image = None
    bands = [(0, scene.height)] if whole else row_bands(scene.width, scene.height, spp)
    for band, (r0, r1) in enumerate(bands):
        rows = None if (r0, r1) == (0, scene.height) else (r0, r1)
        out = np.array(mi.render(mi.load_dict(scene_dict(rows)), spp=spp, seed=band_seed(seed, band)), dtype=np.float64)
        if image is None:
            image = np.empty((scene.height, scene.width, out.shape[-1]))
        image[r0:r1] = out
    return image
