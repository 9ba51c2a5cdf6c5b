"""Phong ground truth with Mitsuba 3: the same formula at every sample, box filter.

A Python :class:`mitsuba.SamplingIntegrator` (registered as ``aaeval_phong``) evaluates
:func:`aaeval.specular.shading.phong`'s formula at the first hit of every camera sample:

    I = C (ka + kd max(N.L, 0)) + ks max(R.E, 0)^n,   R = 2 (N.L) N - L,  E = (0, 0, -1)

with N Mitsuba's shading normal ``si.sh_frame.n`` — the renormalised barycentric blend of
the vertex normals (Phong interpolation) — of the same triangles, vertex normals,
material and light that the Catmull renderer shades. Flat polygons and the background
return their colour. A second output channel (AOV ``specular``) carries the specular
term alone, for highlight metrics.

Camera, variant choice and depth mapping are the flat-colour ground truth's
(:mod:`aaeval.groundtruth.flat`): pixel (col i, row j) is world [i, i+1] x [j, j+1],
the view runs along +z, scene depths are mapped affinely onto camera depths. Under that
map the scene's x, y and the direction of +z are kept, so E and the light direction are
the same vectors in Mitsuba's world; a point light's depth is mapped like the geometry's.
"""

from __future__ import annotations

import numpy as np

from aaeval.groundtruth.flat import (
    DEFAULT_SAMPLER,
    DEFAULT_SPP,
    DEPTH_SPAN,
    NEAR,
    SAMPLERS,
    orthographic_sensor,
    render_in_bands,
    triangulate_scene,
)
from aaeval.mitsuba_variant import import_mitsuba
from aaeval.scenes import Scene
from aaeval.scenes.shaded import expand_shaded

__all__ = [
    "INTEGRATOR",
    "phong_integrator",
    "phong_scene_dict",
    "render_mitsuba_phong",
]

INTEGRATOR = "aaeval_phong"
_REGISTERED: set[str] = set()


def phong_integrator(mi):
    """Register (once per variant) and return the Phong integrator class for ``mi``'s variant."""
    import drjit as dr

    variant = mi.variant()

    class PhongIntegrator(mi.SamplingIntegrator):
        """First-hit Phong shading with per-face materials (mesh attributes)."""

        def __init__(self, props):
            super().__init__(props)
            self.point = bool(props.get("point_light", False))
            v = props.get("light", mi.ScalarPoint3f(0.0, 0.0, -1.0))
            self.light = mi.Point3f(v[0], v[1], v[2])
            # camera depth d -> scene depth z = z0 + (d - d0) * dz
            self.depth_map = (props.get("z0", 0.0), props.get("d0", 0.0), props.get("dz", 1.0))

        def sample(self, scene, sampler, ray, medium=None, active=True):
            si = scene.ray_intersect(ray, active)
            valid = active & si.is_valid()
            shape = si.shape
            color = shape.eval_attribute_3("face_color", si, valid)
            coefficients = shape.eval_attribute_3("face_phong", si, valid)  # ka, kd, ks
            exponent = shape.eval_attribute_1("face_exponent", si, valid)
            shaded = shape.eval_attribute_1("face_shaded", si, valid) > 0.5
            N = dr.normalize(si.sh_frame.n)
            if self.point:
                z0, d0, dz = self.depth_map
                p = mi.Point3f(si.p.x, si.p.y, z0 + (si.p.z - d0) * dz)
                L = dr.normalize(self.light - p)
            else:
                L = dr.normalize(mi.Vector3f(self.light))
            ndotl = dr.dot(N, L)
            R = 2.0 * ndotl * N - L
            rdote = dr.maximum(-R.z, 0.0)  # E = (0, 0, -1)
            specular = coefficients.z * dr.power(rdote, exponent)
            phong = color * (coefficients.x + coefficients.y * dr.maximum(ndotl, 0.0)) + specular
            rgb = dr.select(shaded, phong, color)
            specular = dr.select(valid & shaded, specular, 0.0)
            return dr.select(valid, rgb, 0.0), valid, [specular]

        def aov_names(self):
            return ["specular"]

        def to_string(self):
            return "PhongIntegrator[aaeval]"

    if variant not in _REGISTERED:
        mi.register_integrator(INTEGRATOR, lambda props: PhongIntegrator(props))
        _REGISTERED.add(variant)
    return PhongIntegrator


def _mesh(mi, expanded):
    """One Mitsuba mesh: every drawable polygon (ear-cut, unclipped) with vertex normals."""
    scene, field = expanded.scene, expanded.field
    # a margin wider than any vertex: no clipping, so every triangle keeps its vertices
    # and their unit normals (clipped vertices would need blended, non-unit normals)
    reach = max((np.abs(p.xy).max() for p in scene.polygons), default=0.0)
    tris = triangulate_scene(scene, margin=reach + scene.width + scene.height + 1.0)
    owner_of_vertex = np.zeros(len(tris.vertices), dtype=np.int64)
    owner_of_vertex[tris.faces.ravel()] = np.repeat(tris.polygon, 3)
    normals = np.tile([0.0, 0.0, -1.0], (len(tris.vertices), 1))
    shaded_vertex = field.shaded[owner_of_vertex] if len(owner_of_vertex) else np.zeros(0, bool)
    if shaded_vertex.any():
        v = tris.vertices[shaded_vertex]
        normals[shaded_vertex] = field.normals(owner_of_vertex[shaded_vertex], v[:, 0], v[:, 1])
    # background quad behind everything
    w, h, m = scene.width, scene.height, 1.0
    back = NEAR + DEPTH_SPAN + 1.0
    bg_vertices = np.array([[-m, -m, back], [w + m, -m, back], [w + m, h + m, back], [-m, h + m, back]])
    vertices = np.concatenate([tris.vertices, bg_vertices])
    faces = np.concatenate([tris.faces, np.array([[0, 1, 2], [0, 2, 3]]) + len(tris.vertices)])
    normals = np.concatenate([normals, np.tile([0.0, 0.0, -1.0], (4, 1))])
    owner = np.concatenate([tris.polygon, [-1, -1]])

    def per_face(values, background):
        table = np.vstack([np.asarray(values, dtype=np.float64).reshape(len(scene.polygons), -1),
                           np.atleast_2d(background)])
        return np.ascontiguousarray(table[owner], dtype=np.float32).ravel()

    mesh = mi.Mesh("shaded", len(vertices), len(faces), has_vertex_normals=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = np.ascontiguousarray(vertices, dtype=np.float32).ravel()
    params["vertex_normals"] = np.ascontiguousarray(normals, dtype=np.float32).ravel()
    params["faces"] = np.ascontiguousarray(faces, dtype=np.uint32).ravel()
    params.update()
    mesh.add_attribute("face_color", 3, per_face(field.color, scene.background))
    mesh.add_attribute("face_phong", 3, per_face(np.stack([field.ka, field.kd, field.ks], 1), [0.0, 0.0, 0.0]))
    mesh.add_attribute("face_exponent", 1, per_face(field.n, [0.0]))
    mesh.add_attribute("face_shaded", 1, per_face(field.shaded.astype(np.float64), [0.0]))
    return mesh, tris


def _depth_map(scene: Scene) -> tuple[float, float, float]:
    """(z0, d0, dz): the affine camera-depth -> scene-depth map of triangulate_scene."""
    finite = [p for p in scene.polygons if np.isfinite(p.plane).all()]
    if not finite:
        return 0.0, NEAR, 1.0
    zmin = min(p.vertices[:, 2].min() for p in finite)
    zmax = max(p.vertices[:, 2].max() for p in finite)
    if zmax == zmin:
        return zmin, NEAR + DEPTH_SPAN / 2, 0.0
    return zmin, NEAR, (zmax - zmin) / DEPTH_SPAN


def phong_scene_dict(scene: Scene, *, spp: int, sampler: str = DEFAULT_SAMPLER, rows=None, mi=None, mesh=None) -> dict:
    """The ``mi.load_dict`` dictionary of a shaded scene with the Phong integrator."""
    expanded = expand_shaded(scene)
    phong_integrator(mi)
    if mesh is None:
        mesh, _ = _mesh(mi, expanded)
    light = expanded.field.light
    z0, d0, dz = _depth_map(expanded.scene)
    return {
        "type": "scene",
        "integrator": {
            "type": INTEGRATOR,
            "point_light": light is not None and light.kind == "point",
            "light": mi.ScalarPoint3f(*(light.vector if light is not None else [0.0, 0.0, -1.0])),
            "z0": float(z0),
            "d0": float(d0),
            "dz": float(dz),
        },
        "sensor": orthographic_sensor(scene.width, scene.height, sampler=sampler, spp=spp, rows=rows),
        "shaded": mesh,
    }


def render_mitsuba_phong(
    scene: Scene, *, spp: int = DEFAULT_SPP, sampler: str = DEFAULT_SAMPLER, seed: int = 0, variant: str = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """Render a shaded scene with Mitsuba's Phong integrator (not cached: see :mod:`.cache`).

    Returns
    -------
    rgb : ndarray (H, W, 3) float64
        Box-filtered Phong image (mean of ``spp`` samples per pixel).
    specular : ndarray (H, W) float64
        Box-filtered specular term alone.
    """
    if sampler not in SAMPLERS:
        raise ValueError(f"unknown sampler {sampler!r}; use one of {', '.join(SAMPLERS)}")
    mi = import_mitsuba(variant)
    phong_integrator(mi)
    mesh, _ = _mesh(mi, expand_shaded(scene))
    out = render_in_bands(
        mi, scene, spp=spp, seed=seed,
        scene_dict=lambda rows: phong_scene_dict(scene, spp=spp, sampler=sampler, rows=rows, mi=mi, mesh=mesh),
    )
    return out[..., :3], out[..., -1]
