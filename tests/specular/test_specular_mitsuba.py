"""The Mitsuba Phong ground truth evaluates the same formula as aaeval's shading, and puts
the highlight where the cylinder's geometry (computed in the test) says it is."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.renderers import render
from aaeval.catmull import visible_fragments
from aaeval.scenes import parse_scene
from aaeval.scenes.shaded import expand_shaded
from aaeval.groundtruth import groundtruth_phong
from aaeval.groundtruth import phong as phong_gt
from aaeval.specular.render import scaled_scene
from aaeval.specular.shading import phong

from tests.helpers.shaded_scenes import small_scene


@pytest.fixture(scope="module")
def mi():
    from aaeval.mitsuba_variant import import_mitsuba

    return import_mitsuba("auto")


@pytest.mark.parametrize("light", [None, {"type": "point", "position": [12.0, 8.0, -40.0]}])
def test_integrator_and_aaeval_shade_the_same_points(mi, light):
    import drjit as dr

    scene = parse_scene(small_scene(light=light))
    expanded = expand_shaded(scene)
    k = 8
    fine = visible_fragments(scaled_scene(expanded.scene, k))
    # points in 1/k-pixel cells wholly covered by one shaded polygon: both renderers agree
    # on what is visible there, so only the shading is compared
    whole = (fine.area > 1 - 1e-12) & (fine.polygon >= 0)
    whole &= expanded.field.shaded[np.maximum(fine.polygon, 0)]
    rng = np.random.default_rng(0)
    cell = fine.pixel[whole]
    poly = fine.polygon[whole]
    x = (cell % (scene.width * k) + rng.uniform(0.05, 0.95, len(cell))) / k
    y = (cell // (scene.width * k) + rng.uniform(0.05, 0.95, len(cell))) / k
    assert len(cell) > 1000

    loaded = mi.load_dict(phong_gt.phong_scene_dict(scene, spp=1, mi=mi))
    ray = mi.Ray3f(mi.Point3f(x, y, 0.0), mi.Vector3f(0.0, 0.0, 1.0))
    rgb_mi, valid, (spec_mi,) = loaded.integrator().sample(loaded, loaded.sensors()[0].sampler(), ray)
    rgb_mi = np.stack([np.array(rgb_mi.x), np.array(rgb_mi.y), np.array(rgb_mi.z)], axis=1)
    assert np.array(valid).all()

    field = expanded.field
    N = field.normals(poly, x, y)
    L = field.light_directions(poly, x, y)
    rgb, spec = phong(N, L, field.color[poly], field.ka[poly], field.kd[poly], field.ks[poly], field.n[poly])
    assert spec.max() > 0.1  # the points include some highlight
    # Mitsuba computes in float32: n = 200 amplifies R.E's rounding about 200-fold
    np.testing.assert_allclose(rgb_mi, rgb, atol=2e-4)
    np.testing.assert_allclose(np.array(spec_mi), spec, atol=2e-4)


def test_ground_truth_agrees_with_crow_everywhere(mi, tmp_path, monkeypatch):
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = parse_scene(small_scene())
    rgb, spec = phong_gt.render_mitsuba_phong(scene, spp=1024, sampler="stratified")
    # the registered method dispatches shaded scenes to the Phong integrator (and caches)
    method = render(scene, "mitsuba:spp=1024,sampler=stratified")
    np.testing.assert_array_equal(method, rgb)
    assert groundtruth_phong(scene, spp=1024, sampler="stratified")[2]  # a cache hit now
    crow = render(scene, "catmull:specular=crow,k=16,region=all")
    plain = render(scene, "catmull")
    err_crow = np.sqrt(np.mean((crow - rgb) ** 2))
    err_plain = np.sqrt(np.mean((plain - rgb) ** 2))
    assert err_crow < 2e-3 and err_crow < err_plain / 4
    assert spec.max() > 0.1 and spec.min() >= 0.0


def test_ground_truth_highlight_sits_where_the_normal_is_the_half_vector(mi, tmp_path, monkeypatch):
    """The integrator shares aaeval's formula, so it is checked against geometry: a flipped
    light or eye direction in it moves the peak by several pixels."""
    from tests.helpers.shaded_scenes import CX, CY, RADIUS, cylinder_document, half_vector_column

    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = parse_scene(cylinder_document(), source="<cylinder>")
    _, specular, _ = groundtruth_phong(scene, spp=256, sampler="stratified")
    profile = specular[int(CY)]
    i = int(np.argmax(profile))
    a, b, c = profile[i - 1], profile[i], profile[i + 1]
    peak = i + 0.5 + 0.5 * (a - c) / (a - 2 * b + c)
    assert abs(half_vector_column() - CX) > 0.2 * RADIUS
    assert peak == pytest.approx(half_vector_column(), abs=0.25)
