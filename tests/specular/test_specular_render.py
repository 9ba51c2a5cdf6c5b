"""Shaded scenes, Phong rendering by Catmull visibility, detection and clamping."""

from __future__ import annotations

import copy
import pathlib

import numpy as np
import pytest

from tests.helpers.shaded_scenes import LIGHT, MATERIAL, small_scene
from aaeval.renderers import render
from aaeval.catmull import resolve_flat, visible_fragments
from aaeval.scenes import SceneError, load_scene, parse_scene
from aaeval.scenes.shaded import expand_shaded, tessellate_cylinder
from aaeval.specular.render import SPECULAR_METHODS, render_shaded, specular_aliasing_map

@pytest.fixture(scope="module")
def scene():
    return parse_scene(small_scene(), source="<small>")


# --- oracle: point-sampled box filter, written independently of aaeval's shading -----


def oracle_image(scene, samples_per_side: int) -> np.ndarray:
    """Box-filtered Phong image by a regular grid of point samples per pixel.

    Visibility by barycentric point-in-triangle tests and depth interpolation over every
    triangle; shading I = C (ka + kd max(N.L,0)) + ks max(R.E,0)^n written out here.
    """
    expanded = expand_shaded(scene)
    polys = expanded.scene.polygons
    field = expanded.field
    W, H, s = scene.width, scene.height, samples_per_side
    # sample at the centres of the s x s sub-cells of every pixel
    px, py = np.meshgrid((np.arange(W * s) + 0.5) / s, (np.arange(H * s) + 0.5) / s)
    px, py = px.ravel(), py.ravel()
    depth = np.full(px.shape, np.inf)
    colour = np.tile(scene.background, (px.size, 1))
    for i, p in enumerate(polys):
        v = p.vertices
        if len(v) == 3:
            (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = v
            det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
            if abs(det) < 1e-12:
                continue
            l1 = ((px - x0) * (y2 - y0) - (x2 - x0) * (py - y0)) / det
            l2 = ((x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)) / det
            l0 = 1 - l1 - l2
            inside = (l0 >= 0) & (l1 >= 0) & (l2 >= 0)
            z = l0 * z0 + l1 * z1 + l2 * z2
        else:  # the axis-aligned-ish backdrop quad: split into two triangles' union via plane
            from matplotlib.path import Path

            inside = Path(v[:, :2]).contains_points(np.stack([px, py], 1))
            a, b, c = p.plane
            z = a * px + b * py + c
        front = inside & (z < depth)
        if not front.any():
            continue
        depth[front] = z[front]
        if not field.shaded[i]:
            colour[front] = p.color
            continue
        tri_normals = _vertex_normals_of(expanded, i)
        N = l0[front, None] * tri_normals[0] + l1[front, None] * tri_normals[1] + l2[front, None] * tri_normals[2]
        N /= np.linalg.norm(N, axis=1, keepdims=True)
        light = _light_towards(field.light, p, px[front], py[front])
        ndotl = np.sum(N * light, axis=1)
        R = 2 * ndotl[:, None] * N - light
        rdote = np.maximum(-R[:, 2], 0.0)
        colour[front] = p.color * (field.ka[i] + field.kd[i] * np.maximum(ndotl, 0))[:, None] + (
            field.ks[i] * rdote ** field.n[i]
        )[:, None]
    return colour.reshape(H, s, W, s, 3).mean(axis=(1, 3))


def _light_towards(light, polygon, x, y):
    if light.kind == "directional":
        return np.tile(light.vector / np.linalg.norm(light.vector), (len(x), 1))
    a, b, c = polygon.plane
    d = light.vector - np.stack([x, y, a * x + b * y + c], axis=1)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _vertex_normals_of(expanded, i):
    """Recover the vertex normals of triangle i from its normal field at its vertices."""
    v = expanded.scene.polygons[i].vertices
    return expanded.field.normals(np.full(3, i), v[:, 0], v[:, 1])


# --- scene extension -----------------------------------------------------------------


def test_tessellated_cylinder_vertices_and_normals():
    v, n, t = tessellate_cylinder([0, 0, 0], [0, 0, 2], (3.0, 3.0), 4.0, 12, caps=False)
    np.testing.assert_allclose(np.linalg.norm(v[:, :2], axis=1), 3.0)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0)
    np.testing.assert_allclose(n[:, 2], 0.0, atol=1e-15)  # side normals are radial
    np.testing.assert_allclose(n[:, :2], v[:, :2] / 3.0, atol=1e-15)
    assert t.shape == (24, 3)


def test_cone_normals_are_perpendicular_to_the_surface():
    v, n, t = tessellate_cylinder([0, 0, 0], [0, 0, 1], (2.0, 0.0), 4.0, 8, caps=False)
    for tri in t:
        # the surface line from a base vertex to the apex is tangent: normal . line = 0
        base, apex = tri[0], tri[2]
        line = v[apex] - v[base]
        assert abs(n[base] @ line) < 1e-12 and abs(n[apex] @ (v[apex] - v[tri[1]])) < 0.5


def test_normal_field_reproduces_vertex_normals(scene):
    expanded = expand_shaded(scene)
    i = len(scene.polygons) + 5
    v = expanded.scene.polygons[i].vertices
    cyl = scene.extensions["shaded"].objects[0]
    normals = expanded.field.normals(np.full(3, i), v[:, 0], v[:, 1])
    # each vertex of the triangle is a mesh vertex; its normal is the mesh's normal there
    for vert, normal in zip(v, normals):
        j = np.flatnonzero(np.all(np.isclose(cyl.vertices, vert), axis=1))
        assert any(np.allclose(cyl.normals[k], normal) for k in j)


def test_expansion_keeps_core_polygons_first(scene):
    expanded = expand_shaded(scene)
    assert expanded.scene.polygons[0] is scene.polygons[0]
    assert [p.index for p in expanded.scene.polygons] == list(range(len(expanded.scene.polygons)))
    assert expanded.field.shaded.sum() == len(expanded.scene.polygons) - 1


def test_frames_translate_and_spin_objects():
    doc = small_scene(frames=4, spin=2.0, translate=(0.25, -0.5))
    scene = parse_scene(doc)
    e0 = expand_shaded(scene).scene.polygons
    e2 = expand_shaded(scene.at_frame(2)).scene.polygons
    centre0 = np.mean([p.vertices[:, :2].mean(0) for p in e0[1:]], axis=0)
    centre2 = np.mean([p.vertices[:, :2].mean(0) for p in e2[1:]], axis=0)
    # the cone does not spin and the cylinder spins about its centre: the mean moves by
    # the translation, up to the cylinder's rotation about its own centre (zero mean shift)
    np.testing.assert_allclose(centre2 - centre0, [0.5, -1.0], atol=1e-9)
    assert not np.allclose(e0[5].vertices[:, :2] + [0.5, -1.0], e2[5].vertices[:, :2])


@pytest.mark.parametrize(
    "patch, message",
    [
        (lambda d: d["shaded"].pop("light"), "light"),
        (lambda d: d["shaded"]["cylinders"][0].update(radius=-1), "radius"),
        (lambda d: d["shaded"]["cylinders"][0]["material"].pop("ks"), "ks"),
        (lambda d: d["shaded"]["cylinders"][0].update(colour=[1, 1, 1]), "unknown"),
        (lambda d: d["shaded"].update(light={"type": "spot", "direction": [0, 0, -1]}), "spot"),
        (lambda d: d["shaded"]["cones"][0].update(segments=2), "segments"),
        (lambda d: d["shaded"].update(meshes=[{"vertices": [[0, 0, 0]], "normals": [[0, 0, 1]],
                                               "triangles": [[0, 0, 1]], "material": MATERIAL}]), "triangles"),
    ],
)
def test_bad_shaded_tables_are_refused(patch, message):
    doc = copy.deepcopy(small_scene())
    patch(doc)
    with pytest.raises(SceneError, match=message):
        parse_scene(doc, source="bad.toml")


def test_mesh_objects_render():
    doc = small_scene()
    doc["shaded"] = {
        "light": {"type": "point", "position": [12.0, 10.0, -40.0]},
        "meshes": [{
            "vertices": [[4, 4, 10], [20, 5, 12], [12, 17, 8]],
            "normals": [[-0.3, -0.3, -1], [0.4, -0.2, -1], [0, 0.5, -1]],
            "triangles": [[0, 1, 2]], "material": MATERIAL,
        }],
    }
    scene = parse_scene(doc)
    crow = render(scene, "catmull:specular=crow,k=4,region=all")
    # pixels wholly inside the triangle: every sub-cell is whole, its centroid is the
    # oracle's sample point, so the two agree to rounding
    from matplotlib.path import Path

    corners = np.stack(np.meshgrid(np.arange(25), np.arange(21)), -1).reshape(-1, 2)
    inside = Path(np.array([[4, 4], [20, 5], [12, 17]])).contains_points(corners).reshape(21, 25)
    whole = inside[:-1, :-1] & inside[1:, :-1] & inside[:-1, 1:] & inside[1:, 1:]
    assert whole.sum() > 40
    np.testing.assert_allclose(crow[whole], oracle_image(scene, 4)[whole], atol=1e-12)
    # elsewhere (edges, point-sampled coverage in the oracle) they agree to sampling error
    assert np.sqrt(np.mean((crow - oracle_image(scene, 16)) ** 2)) < 0.01


# --- flat scenes unchanged -----------------------------------------------------------


@pytest.mark.parametrize("specular", SPECULAR_METHODS)
def test_flat_scenes_render_as_before(specular, scene):
    flat = parse_scene({k: v for k, v in small_scene().items() if k != "shaded"})
    expected = render(flat, "catmull")
    assert np.array_equal(render(flat, f"catmull:specular={specular}"), expected)
    # the flat path skips the pieces' centroids: the same areas, up to the last bit
    np.testing.assert_allclose(expected, resolve_flat(flat, visible_fragments(flat)), rtol=0, atol=1e-14)


def test_scene_files_without_shaded_tables_still_load(tmp_path):
    path = tmp_path / "flat.toml"
    path.write_text('[image]\nwidth = 4\nheight = 4\n[[polygons]]\ncolor = [1, 0, 0]\n'
                    'vertices = [[0.5, 0.5, 1], [3.5, 1, 1], [2, 3.5, 1]]\n')
    scene = load_scene(path)
    assert scene.extensions == {}
    assert np.array_equal(render(scene, "catmull"), resolve_flat(scene, visible_fragments(scene, centroids=False)))


# --- ground truth convergence and clamping ---------------------------------------------


def test_crow_everywhere_matches_point_sampled_oracle(scene):
    # both are the average of the same Phong function over the same k x k sub-cells,
    # crow by exact sub-cell visibility and centroid shading, the oracle by centre samples
    k = 6
    crow = render(scene, f"catmull:specular=crow,k={k},region=all")
    oracle = oracle_image(scene, k)
    fine = oracle_image(scene, 18)
    # crow's error against the fine oracle is no larger than the point sampler's at k
    err_crow = np.sqrt(np.mean((crow - fine) ** 2))
    err_oracle = np.sqrt(np.mean((oracle - fine) ** 2))
    assert err_crow < 1.2 * err_oracle
    assert err_crow < 0.01


def test_crow_converges_as_k_grows(scene):
    reference = render(scene, "catmull:specular=crow,k=16,region=all")
    errors = [np.abs(render(scene, f"catmull:specular=crow,k={k},region=all") - reference).max() for k in (1, 2, 4)]
    assert errors[0] > errors[1] > errors[2]
    # k = 1 shades each piece once at its centroid: that is specular=none
    assert np.allclose(render(scene, "catmull:specular=crow,k=1,region=all"), render(scene, "catmull"), atol=1e-12)


@pytest.mark.parametrize(
    "spec", ["amanatides", "amanatides,power=0.999", "amanatides,power=0.99", "crow,k=3"]
)
def test_clamping_changes_only_flagged_pixels(scene, spec):
    power = float(spec.split("power=")[1]) if "power=" in spec else 1.0
    flags = specular_aliasing_map(scene, power=power).flag
    plain = render(scene, "catmull")
    clamped = render(scene, f"catmull:specular={spec}")
    assert flags.any() and (~flags).any()
    assert np.array_equal(plain[~flags], clamped[~flags])
    assert not np.allclose(plain[flags], clamped[flags])


def test_detection_rate_exceeds_one_exactly_where_flagged(scene):
    for power in (1.0, 0.999):
        m = specular_aliasing_map(scene, power=power)
        assert np.array_equal(m.flag, m.rate > 1.0)
    conservative = specular_aliasing_map(scene)
    aggressive = specular_aliasing_map(scene, power=0.99)
    assert (aggressive.flag <= conservative.flag).all()
    on = conservative.rate > 0
    # a fraction of the power has a lower cutoff than the highest frequency n
    assert (aggressive.rate[on] < conservative.rate[on]).all()


def test_conservative_clamp_never_brightens_the_peak(scene):
    # n' <= n and ks' = ks Maximum[n]/Maximum[n']: the clamped peak ks' <= ks
    _, spec_plain = render_shaded(scene, return_specular=True)
    _, spec_clamped = render_shaded(scene, specular="amanatides", return_specular=True)
    assert spec_clamped.max() <= 0.8 + 1e-12
    assert spec_plain.max() <= 0.8 + 1e-12


@pytest.mark.parametrize("specular", ["toksvig", "vlachos", "tokuyoshi"])
def test_modern_methods_widen_only_where_normals_turn(specular):
    # a flat-normal triangle: no derivative, so nothing changes
    doc = small_scene()
    doc["shaded"] = {
        "light": {"type": "directional", "direction": LIGHT},
        "meshes": [{"vertices": [[2, 2, 5], [22, 3, 5], [10, 18, 5]], "normals": [[0.1, -0.05, -1]] * 3,
                    "triangles": [[0, 1, 2]], "material": MATERIAL}],
    }
    flat_normals = parse_scene(doc)
    np.testing.assert_allclose(render(flat_normals, f"catmull:specular={specular}"), render(flat_normals, "catmull"), atol=1e-12)


def test_shaded_scene_files_load_and_render():
    shipped = pathlib.Path(__file__).resolve().parents[2] / "configs" / "scenes" / "shaded"
    for name in ("cylinders", "cones"):
        scene = load_scene(shipped / f"{name}.toml")
        assert len(scene.extensions["shaded"].objects) >= 2 and scene.frames > 1
        image = render(scene, "catmull:specular=none", frame=scene.frames - 1)
        assert image.shape == (scene.height, scene.width, 3) and np.isfinite(image).all()
        # the objects are lit: well above the background somewhere, with a highlight
        assert (image - scene.background).max() > 0.1, name


def test_detection_matches_the_analytic_normal_turn_of_a_cylinder():
    # a vertical cylinder seen side-on: the normal at x is (sin t, 0, -cos t) with
    # sin t = (x - cx) / R, turning at dt/dx = 1 / sqrt(R^2 - (x - cx)^2). Each facet's
    # normal field is linear across the pixel at the facet's own rate, and detection
    # takes the most turning facet of the pixel: the turn lies between the rates at
    # the pixel's two sides
    R, cx, n = 20.0, 16.0, 29
    doc = {
        "image": {"width": 32, "height": 32},
        "shaded": {
            "light": {"type": "directional", "direction": [0.0, 0.0, -1.0]},
            "cylinders": [{"centre": [cx, 16.0, 100.0], "axis": [0.0, 1.0, 0.0], "radius": R, "length": 40.0,
                           "segments": 720, "caps": False, "material": {**MATERIAL, "n": n}}],
        },
    }
    m = specular_aliasing_map(parse_scene(doc))
    # away from the silhouette, where one facet's linear normal field, extended over the
    # pixel, follows the circle closely
    cols = np.arange(6, 26)
    rate = 1 / np.sqrt(R**2 - (np.stack([cols, cols + 1]) - cx) ** 2)
    turn = np.arccos(m.dot[16, cols])
    assert (turn >= rate.min(axis=0) * (1 - 2e-3)).all() and (turn <= rate.max(axis=0) * (1 + 2e-3)).all()
    threshold = np.pi / (2 * n)  # MinDot[n] = cos(pi / 2n)
    np.testing.assert_array_equal(m.flag[16, cols], turn > threshold)
    assert m.flag[16, cols].any() and not m.flag[16, cols].all()
    np.testing.assert_allclose(m.rate[16, cols], turn / threshold, rtol=1e-9)

