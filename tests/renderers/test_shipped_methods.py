"""The methods engines ship: MSAA, FXAA 3.11, TAA.

Published values are written here, not read from the code: the D3D11 standard sample
patterns (as Mesa's OpenSWR rasterizer tabulates them, 1/256 pixel from the pixel's
corner), FXAA 3.11's response worked out by hand from the shader source, the Halton(2, 3)
points. Temporal behaviour is measured with the project's metrics
(aaeval.metrics.temporal).
"""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.metrics.temporal import flicker, temporal_bias
from aaeval.renderers import render
from aaeval.scenes import parse_scene

# D3D11_STANDARD_MULTISAMPLE_PATTERN, from Mesa src/gallium/drivers/swr/rasterizer/core/multisample.h
# (samplePosXi / samplePosYi: 0x80 is the pixel centre, 0x10 is 1/16 pixel)
SWR_X = {
    2: [0xC0, 0x40],
    4: [0x60, 0xE0, 0x20, 0xA0],
    8: [0x90, 0x70, 0xD0, 0x50, 0x30, 0x10, 0xB0, 0xF0],
    16: [0x90, 0x70, 0x50, 0xC0, 0x30, 0xA0, 0xD0, 0xB0, 0x60, 0x80, 0x40, 0x20, 0x00, 0xF0, 0xE0, 0x10],
}
SWR_Y = {
    2: [0xC0, 0x40],
    4: [0x20, 0x60, 0xA0, 0xE0],
    8: [0x50, 0xB0, 0x90, 0x30, 0xD0, 0x70, 0xF0, 0x10],
    16: [0x90, 0x50, 0xA0, 0x70, 0x60, 0xD0, 0xB0, 0x30, 0xE0, 0x10, 0x20, 0xC0, 0x80, 0x40, 0xF0, 0x00],
}


def published(samples):
    """Offsets from the pixel centre in pixels, (samples, 2)."""
    return np.column_stack([(np.array(SWR_X[samples]) - 0x80) / 256.0, (np.array(SWR_Y[samples]) - 0x80) / 256.0])


def rect(x0, y0, x1, y1, z=1.0, color=(1.0, 1.0, 1.0)):
    return {"color": list(color), "vertices": [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]}


def scene_of(polygons, width, height, background=(0.0, 0.0, 0.0), animation=None):
    doc = {"image": {"width": width, "height": height, "background": list(background)}, "polygons": polygons}
    if animation:
        doc["animation"] = animation
    return parse_scene(doc)


# --- MSAA ----------------------------------------------------------------------------


@pytest.mark.parametrize("samples", [2, 4, 8, 16])
def test_msaa_pattern_is_the_published_one(samples):
    from aaeval.renderers.msaa import sample_offsets

    np.testing.assert_array_equal(np.sort(sample_offsets(samples), axis=0), np.sort(published(samples), axis=0))
    np.testing.assert_array_equal(sample_offsets(samples), published(samples))  # the same order too


@pytest.mark.parametrize("samples", [2, 4, 8, 16])
def test_msaa_samples_where_the_pattern_says(samples):
    # a 1x1 pixel: a polygon covering x < 1/2 + t (or y < 1/2 + t) covers the samples with
    # offset below t; edges between the 1/16 positions count every sample once
    pattern = published(samples)
    for t in (np.arange(-8, 8) + 0.5) / 16:
        for axis in (0, 1):
            poly = rect(-2, -2, 0.5 + t, 3) if axis == 0 else rect(-2, -2, 3, 0.5 + t)
            image = render(scene_of([poly], 1, 1), f"msaa:samples={samples}")
            expected = np.mean(pattern[:, axis] < t)
            assert image[0, 0, 0] == pytest.approx(expected, abs=1e-15), (axis, t)


def test_msaa_one_sample_is_point():
    from tests.helpers.randomscenes import random_scene

    scene = random_scene(3)
    np.testing.assert_array_equal(render(scene, "msaa:samples=1"), render(scene, "point"))


@pytest.mark.parametrize("gap", [0.0, 1e-13, 1.5e-11])
@pytest.mark.parametrize("method", ["msaa:samples=8", "fxaa", "taa:warmup=4"])
def test_near_tie_rule(method, gap):
    # eps = 1e-11 (1 + max |z|) ~ 2e-11: the later, farther square is tied and visible;
    # beyond eps the nearer one is
    for z2, colour in ((1 + gap, [0, 0, 1]), (1 + 1e-9, [1, 0, 0])):
        scene = scene_of([rect(2, 2, 12, 12, 1.0, (1, 0, 0)), rect(4, 4, 14, 14, z2, (0, 0, 1))], 16, 16)
        np.testing.assert_allclose(render(scene, method)[8, 8], colour, atol=1e-12)


SHADED = {
    "image": {"width": 24, "height": 20, "background": [0.0, 0.0, 0.0]},
    "polygons": [],
    "shaded": {
        "light": {"type": "directional", "direction": [0.3, -0.2, -1.0]},
        "meshes": [{
            "vertices": [[-2, -2, 10], [26, -2, 10], [26, 22, 10], [-2, 22, 10]],
            "normals": [[-0.7, -0.5, -0.5], [0.7, -0.5, -0.5], [0.6, 0.6, -0.6], [-0.6, 0.7, -0.4]],
            "triangles": [[0, 1, 2], [0, 2, 3]],
            "material": {"color": [0.7, 0.2, 0.1], "ka": 0.1, "kd": 0.6, "ks": 0.9, "n": 40},
        }],
    },
}


def test_msaa_shades_once_per_pixel_at_the_centre():
    from aaeval.scenes.shaded import expand_shaded
    from aaeval.specular.shading import phong

    scene = parse_scene(SHADED)
    image = render(scene, "msaa:samples=16")
    # away from the diagonal both triangles meet on, all 16 samples see one triangle:
    # its Phong shade at the pixel centre, as one sample there (msaa:samples=1) gives
    rows, cols = np.mgrid[0:20, 0:24]
    far = np.abs((cols + 0.5) - (-2 + (rows + 0.5 + 2) * 28 / 24)) > 2.5  # x from the diagonal
    np.testing.assert_allclose(image[far], render(scene, "msaa:samples=1")[far], rtol=0, atol=1e-14)
    # and that is the Phong formula at the centre (checked at one pixel by hand)
    field = expand_shaded(scene).field
    x, y = np.array([20.5]), np.array([3.5])
    poly = np.array([0])  # the first triangle holds the top right
    rgb, _ = phong(field.normals(poly, x, y), field.light_directions(poly, x, y), field.color[poly],
                   field.ka[poly], field.kd[poly], field.ks[poly], field.n[poly])
    np.testing.assert_allclose(image[3, 20], rgb[0], rtol=1e-12)


# --- FXAA ----------------------------------------------------------------------------

SUBPIX_STEP = 0.75 * (7 / 27) ** 2  # subpixC = 1/3 beside a straight 0/1 step: 0.75 (subpixD subpixE)^2


def grey(luma):
    return np.repeat(np.asarray(luma, dtype=np.float64)[:, :, None], 3, axis=2)


@pytest.mark.parametrize("preset", [12, 39])
def test_fxaa_vertical_step(preset):
    from aaeval.renderers.fxaa import fxaa

    step = np.zeros((6, 8))
    step[:, 4:] = 1.0
    out = fxaa(grey(step), preset=preset)[:, :, 0]
    # the edge search runs to the image border (a straight edge never ends): no edge blend;
    # only the sub-pixel term moves the two pixels beside the step towards each other
    expected = step.copy()
    expected[:, 3] = SUBPIX_STEP
    expected[:, 4] = 1 - SUBPIX_STEP
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)
    # without the sub-pixel term a straight step is left alone
    np.testing.assert_array_equal(fxaa(grey(step), preset=preset, subpix=0.0), grey(step))


def staircase():
    r, c = np.mgrid[0:8, 0:16]
    return (c < 2 * r).astype(float)  # a 1:2 staircase, bright below-left


@pytest.mark.parametrize("preset,subpix,expected", [
    # pixel (1, 2): end of a 2-long step; the search stops at x = 1 (N) and x = 4 (P) with
    # preset 39 (steps 1, 1), at x = 4.5 with preset 12 (steps 1, 1.5): the edge offset is
    # 0.5 - dst / span = 0.5 - 1/3 = 1/6, or 0.5 - 1/3.5 = 3/14; subpixC = 1/2 gives the
    # sub-pixel offset 0.75 (2 * 1/4)^2 = 0.1875, the larger one wins
    (39, 0.75, {(1, 2): 0.1875, (1, 3): 0.75 * (2.5 * 0.0625) ** 2}),
    (39, 0.0, {(1, 2): 1 / 6, (1, 3): 0.0}),
    (12, 0.0, {(1, 2): 3 / 14, (1, 3): 0.0}),
])
def test_fxaa_staircase_published_weights(preset, subpix, expected):
    from aaeval.renderers.fxaa import fxaa

    out = fxaa(grey(staircase()), preset=preset, subpix=subpix, luma="green")[:, :, 1]
    for (r, c), value in expected.items():
        assert out[r, c] == pytest.approx(value, abs=1e-12), (r, c)


def test_fxaa_constant_image_unchanged_and_output_within_range():
    from aaeval.renderers.fxaa import fxaa

    constant = np.full((9, 11, 3), 0.37)
    np.testing.assert_array_equal(fxaa(constant), constant)
    rng = np.random.default_rng(4)
    for _ in range(5):
        image = rng.uniform(0, 1, (17, 13, 3)) ** 3
        out = fxaa(image)
        assert (out >= image.min(axis=(0, 1)) - 1e-15).all() and (out <= image.max(axis=(0, 1)) + 1e-15).all()
    # the method: within the point image's range, in linear RGB
    from tests.helpers.randomscenes import random_scene

    scene = random_scene(3)  # its luma contrasts pass FXAA's thresholds (random_scene(5)'s do not)
    point, filtered = render(scene, "point"), render(scene, "fxaa")
    assert (filtered >= point.min(axis=(0, 1)) - 1e-12).all() and (filtered <= point.max(axis=(0, 1)) + 1e-12).all()
    assert not np.array_equal(point, filtered)


def test_fxaa_works_in_srgb():
    from aaeval.renderers.fxaa import srgb_decode, srgb_encode

    # a vertical 0.2 / 0 step (linear): the pixel beside it moves 0.0504 of the way to the
    # dark side in sRGB-encoded values (blending linear values would give 0.2 * (1 - 0.0504))
    out = render(scene_of([rect(-1, -1, 4, 7, color=(0.2, 0.2, 0.2))], 8, 6), "fxaa")
    expected = srgb_decode((1 - SUBPIX_STEP) * srgb_encode(np.array(0.2)))
    assert out[2, 3, 0] == pytest.approx(float(expected), rel=1e-12)
    # a 0.01 / 0 step: contrast 0.0998 in sRGB luma passes fxaaQualityEdgeThresholdMin
    # (0.0833); in linear luma (0.01) it would not
    dark = render(scene_of([rect(-1, -1, 4, 7, color=(0.01, 0.01, 0.01))], 8, 6), "fxaa")
    assert dark[2, 3, 0] == pytest.approx(float(srgb_decode((1 - SUBPIX_STEP) * srgb_encode(np.array(0.01)))),
                                          rel=1e-12)


def test_fxaa_luma_weights():
    from aaeval.renderers.fxaa import fxaa

    # a blue / black step: luma 0.114 with FXAA 3.11's pre-pass weights (0.299, 0.587, 0.114)
    # passes fxaaQualityEdgeThresholdMin (0.0833) and gets the sub-pixel blend; Rec. 709 weights
    # (0.0722) would not, nor would green as luma (0)
    step = np.zeros((6, 8, 3))
    step[:, :4, 2] = 1.0
    out = fxaa(step)
    assert out[2, 3, 2] == pytest.approx(1 - SUBPIX_STEP, abs=1e-12)
    np.testing.assert_array_equal(fxaa(step, luma="green"), step)


# --- TAA -----------------------------------------------------------------------------

# Halton(2, 3) points 1..8 (radical inverses), the jitter being these minus 1/2
HALTON_8 = [(1 / 2, 1 / 3), (1 / 4, 2 / 3), (3 / 4, 1 / 9), (1 / 8, 4 / 9), (5 / 8, 7 / 9), (3 / 8, 2 / 9),
            (7 / 8, 5 / 9), (1 / 16, 8 / 9)]
TRIANGLES = [
    {"color": [0.9, 0.8, 0.2], "vertices": [[5.3, 4.1, 1], [43.7, 9.6, 1], [15.2, 36.3, 1]]},
    {"color": [0.2, 0.7, 0.9], "vertices": [[20.5, 2.2, 0.5], [40.1, 30.7, 0.5], [28.3, 37.9, 0.5]]},
]


def test_taa_jitter_is_halton_2_3():
    from aaeval.renderers.taa import jitter_sequence

    np.testing.assert_allclose(jitter_sequence(8), np.array(HALTON_8) - 0.5, rtol=0, atol=1e-15)


def _shifted(polygons, dx, dy):
    return [{"color": p["color"], "vertices": [[x + dx, y + dy, z] for x, y, z in p["vertices"]]} for p in polygons]


def test_taa_static_scene_converges_to_the_jittered_supersample():
    # the same 8 jitter positions, averaged: point samples of the scene moved by -offset
    jittered = np.mean([render(scene_of(_shifted(TRIANGLES, 0.5 - u, 0.5 - v), 48, 40, (0.1, 0.2, 0.3)), "point")
                        for u, v in HALTON_8], axis=0)
    static = scene_of(TRIANGLES, 48, 40, (0.1, 0.2, 0.3), animation={"frames": 8, "translate": [0.0, 0.0]})
    frames = np.stack([render(static, "taa", frame=k) for k in range(8)])
    # exponential blending leaves a ripple of order alpha on edge pixels in every frame;
    # over one jitter cycle after the warm-up the frames average to the supersample
    cycle_error = np.sqrt(np.mean((frames.mean(axis=0) - jittered) ** 2))
    frame_error = max(np.sqrt(np.mean((f - jittered) ** 2)) for f in frames)
    assert cycle_error < 1e-3, cycle_error
    assert frame_error < 1e-2, frame_error
    # no warm-up: frame 0 is one jittered sample, far from converged
    assert np.sqrt(np.mean((render(static, "taa:warmup=0", frame=0) - jittered) ** 2)) > 10 * cycle_error


def test_taa_every_frame_converges_when_the_blend_weight_is_small():
    # each frame's own error, not the cycle's mean: with alpha = 0.005 the eight jitter
    # phases carry nearly equal weights in the history (0.995^7 = 0.97), so every frame
    # after a long warm-up is within 1e-3 of the same-jitter supersample; alpha = 0.1
    # (the default, as engines ship it) keeps a ripple of order alpha on edge pixels
    jittered = np.mean([render(scene_of(_shifted(TRIANGLES, 0.5 - u, 0.5 - v), 48, 40, (0.1, 0.2, 0.3)), "point")
                        for u, v in HALTON_8], axis=0)
    static = scene_of(TRIANGLES, 48, 40, (0.1, 0.2, 0.3), animation={"frames": 8, "translate": [0.0, 0.0]})
    errors = [np.sqrt(np.mean((render(static, "taa:alpha=0.005,warmup=2048", frame=k) - jittered) ** 2))
              for k in range(8)]
    assert max(errors) < 1e-3, errors


def edge_animation():
    # a slanted bright bar drifting by (0.13, 0.05) pixel per frame
    bar = {"color": [0.9, 0.9, 0.9], "vertices": [[8.3, -4, 1], [20.7, -4, 1], [14.2, 40, 1], [1.9, 40, 1]]}
    return scene_of([bar], 40, 32, (0.05, 0.05, 0.05), animation={"frames": 24, "translate": [0.13, 0.05]})


@pytest.mark.slow
def test_taa_flickers_less_than_point_on_a_translating_edge():
    scene = edge_animation()
    truth = np.stack([render(scene, "catmull", frame=k) for k in range(scene.frames)])
    measured = {}
    for spec in ("point", "taa", "taa:resample=bilinear,clamp=variance"):
        frames = np.stack([render(scene, spec, frame=k) for k in range(scene.frames)])
        measured[spec] = (flicker(truth, frames), temporal_bias(truth, frames))
    assert measured["taa"][0] < 0.7 * measured["point"][0], measured
    assert measured["taa:resample=bilinear,clamp=variance"][0] < measured["point"][0], measured


def test_taa_frame_is_the_same_alone_or_after_the_previous_ones():
    from aaeval.renderers import taa

    scene = edge_animation()
    in_order = [render(scene, "taa:warmup=8", frame=k) for k in range(6)]
    taa._CACHE.clear()
    alone = render(scene, "taa:warmup=8", frame=5)
    np.testing.assert_array_equal(alone, in_order[5])
    taa._CACHE.clear()
    assert not np.array_equal(render(scene, "taa:warmup=9", frame=5), alone)


@pytest.mark.parametrize("kind", ["bilinear", "catmull-rom"])
def test_taa_reprojection(kind):
    from aaeval.renderers.taa import reproject

    rng = np.random.default_rng(2)
    image = rng.uniform(size=(10, 12, 3))
    # a whole-pixel motion moves the image exactly; pixels whose source is outside are flagged
    out, inside = reproject(image, 2.0, -1.0, kind)
    np.testing.assert_allclose(out[0:9, 2:], image[1:10, 0:10], rtol=0, atol=1e-15)
    assert inside[0:9, 2:].all() and not inside[:, :2].any() and not inside[9].any()
    # a linear ramp is reproduced exactly at a fractional motion (away from the border)
    ramp = np.broadcast_to((np.arange(12) * 0.05)[None, :, None], (10, 12, 3))
    out, _ = reproject(ramp, 0.3, 0.0, kind)
    np.testing.assert_allclose(out[:, 3:-2], ramp[:, 3:-2] - 0.3 * 0.05, rtol=0, atol=1e-14)


def test_taa_carries_spinning_surfaces_back_exactly():
    import copy

    from aaeval.renderers.offsets import OffsetSampler
    from aaeval.renderers.taa import motion_sources

    doc = copy.deepcopy(SHADED)
    doc["shaded"]["meshes"][0].update({"spin": {"axis": [0.0, 0.0, 1.0], "degrees": 2.0}, "pivot": [12.0, 10.0, 10.0]})
    doc["animation"] = {"frames": 3, "translate": [0.3, 0.1]}
    scene = parse_scene(doc)
    now, before = OffsetSampler(scene.at_frame(2)), OffsetSampler(scene.at_frame(1))
    sx, sy = motion_sources(now, before, 0.3, 0.1)
    # the mesh lies in the plane z = 10 and spins about the z axis through its pivot, which
    # moves with the translation: a point at frame 2 was at R(-2 deg)(p - pivot_2) + pivot_1
    rows, cols = np.mgrid[0:20, 0:24]
    x, y = cols + 0.5, rows + 0.5
    pivot2, pivot1 = np.array([12.0 + 0.6, 10.0 + 0.2]), np.array([12.0 + 0.3, 10.0 + 0.1])
    t = np.radians(-2.0)
    ux, uy = x - pivot2[0], y - pivot2[1]
    ex = np.cos(t) * ux - np.sin(t) * uy + pivot1[0]
    ey = np.sin(t) * ux + np.cos(t) * uy + pivot1[1]
    seen = now.ids(0.0, 0.0) >= 0
    assert seen.mean() > 0.9
    np.testing.assert_allclose(sx[seen] + 0.5, ex[seen], rtol=0, atol=1e-9)
    np.testing.assert_allclose(sy[seen] + 0.5, ey[seen], rtol=0, atol=1e-9)
    # the background and flat polygons only translate
    np.testing.assert_allclose(sx[~seen] + 0.5, x[~seen] - 0.3, rtol=0, atol=1e-12)
    frames = np.stack([render(scene, "taa:warmup=8", frame=k) for k in range(3)])
    assert np.isfinite(frames).all()

