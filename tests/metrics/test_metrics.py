"""Image and temporal metrics: perfect scores, published values, independent oracles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from aaeval.metrics import (
    IMAGE_METRICS,
    METRICS,
    TEMPORAL_METRICS,
    MetricError,
    ciede2000_map,
    ciede2000_mean,
    ciede2000_p95,
    compute_metric,
    compute_temporal_metric,
    edge_mask,
    edge_rmse,
    flicker,
    flip,
    linear_rgb_to_lab,
    psnr,
    rmse,
    ssim,
)
from aaeval.scenes import parse_scene

RNG = np.random.default_rng(20241122)
IMAGE = RNG.random((12, 16, 3))
MASK = RNG.random((12, 16)) < 0.3

# the score of a perfect match, for every registered image metric
PERFECT = {
    "rmse": 0.0,
    "psnr": math.inf,
    "ssim": 1.0,
    "ciede2000_mean": 0.0,
    "ciede2000_p95": 0.0,
    "flip": 0.0,
    "edge_rmse": 0.0,
    "highlight_rmse": 0.0,
    "highlight_energy_bias": 0.0,
}

# Sharma, Wu & Dalal (2005), "The CIEDE2000 color-difference formula: implementation
# notes, supplementary test data, and mathematical observations", Table 1 (pair number,
# Lab 1, Lab 2, Delta E 2000), a selection covering the hue-angle edge cases.
SHARMA_2005 = [
    (1, (50.0000, 2.6772, -79.7751), (50.0000, 0.0000, -82.7485), 2.0425),
    (4, (50.0000, -1.3802, -84.2814), (50.0000, 0.0000, -82.7485), 1.0000),
    (7, (50.0000, 0.0000, 0.0000), (50.0000, -1.0000, 2.0000), 2.3669),
    (9, (50.0000, 2.4900, -0.0010), (50.0000, -2.4900, 0.0009), 7.1792),
    (11, (50.0000, 2.4900, -0.0010), (50.0000, -2.4900, 0.0011), 7.2195),
    (13, (50.0000, -0.0010, 2.4900), (50.0000, 0.0009, -2.4900), 4.8045),
    (17, (50.0000, 2.5000, 0.0000), (73.0000, 25.0000, -18.0000), 27.1492),
    (19, (50.0000, 2.5000, 0.0000), (56.0000, -27.0000, -3.0000), 31.9030),
    (25, (60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
    (28, (35.0831, -44.1164, 3.7933), (35.0232, -40.0716, 1.5901), 1.8645),
    (30, (36.4612, 47.8580, 18.3852), (36.2715, 50.5065, 21.2231), 1.4146),
    (33, (6.7747, -0.2908, -2.4247), (5.8714, -0.0985, -2.2286), 0.6377),
    (34, (2.0776, 0.0795, -1.1350), (0.9033, -0.0636, -0.5514), 0.9082),
]


def lab_to_linear_rgb(lab) -> np.ndarray:
    """Inverse of the metric's conversion path, to build test images from Lab colours.

    colour's published sRGB matrices (RGB to XYZ and back) are rounded and not exact
    inverses (Lab error ~4e-3 round trip), so the forward matrix is inverted here.
    """
    import colour

    srgb = colour.RGB_COLOURSPACES["sRGB"]
    xyz = colour.Lab_to_XYZ(np.asarray(lab, dtype=np.float64), srgb.whitepoint)
    return xyz @ np.linalg.inv(srgb.matrix_RGB_to_XYZ).T


def srgb_encode(linear):
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def test_every_registered_metric_has_a_perfect_score_listed():
    assert set(PERFECT) == set(IMAGE_METRICS)


@pytest.mark.parametrize("name", sorted(IMAGE_METRICS))
def test_identical_images_score_perfectly(name):
    value = compute_metric(name, IMAGE, IMAGE.copy(), mask=MASK)
    assert value == pytest.approx(PERFECT[name], abs=1e-12)


@pytest.mark.parametrize("name", sorted(IMAGE_METRICS))
def test_different_images_do_not_score_perfectly(name):
    other = np.clip(IMAGE + RNG.normal(0, 0.05, IMAGE.shape), 0, 1)
    value = compute_metric(name, IMAGE, other, mask=MASK)
    assert np.isfinite(value) and value != pytest.approx(PERFECT[name], abs=1e-6)


@pytest.mark.parametrize("name", sorted(IMAGE_METRICS))
@pytest.mark.parametrize(
    "true, test, message",
    [
        (IMAGE, IMAGE[:-1], "differ in shape"),
        (IMAGE[..., :2], IMAGE[..., :2], r"\(H, W, 3\)"),
        (IMAGE[..., 0], IMAGE[..., 0], r"\(H, W, 3\)"),
        (IMAGE, np.where(MASK[..., None], np.nan, IMAGE), "non-finite"),
        (np.full_like(IMAGE, np.inf), IMAGE, "non-finite"),
    ],
)
def test_bad_inputs_are_refused_before_any_work(name, true, test, message):
    if METRICS[name].mask == "highlight" and true.ndim == 2:
        pytest.skip("highlight metrics also take (H, W) specular-only images")
    with pytest.raises(ValueError, match=message):
        compute_metric(name, true, test, mask=MASK)


def test_constant_offset_gives_the_exact_psnr():
    # MSE = 0.01 on data range 1: PSNR = 10 log10(1 / 0.01) = 20 dB
    base = np.full((8, 8, 3), 0.4)
    assert rmse(base, base + 0.1) == pytest.approx(0.1, rel=1e-12)
    assert psnr(base, base + 0.1) == pytest.approx(20.0, abs=1e-9)
    assert psnr(base, base + 0.1, data_range=2.0) == pytest.approx(20.0 + 20 * math.log10(2), abs=1e-9)


@pytest.mark.parametrize("data_range", [1.0, 2.0])
def test_ssim_of_constant_images_follows_its_closed_form(data_range):
    # constant images: every local variance and covariance is 0, so SSIM per channel is the
    # luminance term (2 a b + C1) / (a^2 + b^2 + C1), C1 = (0.01 L)^2 (Wang et al. 2004)
    a = np.array([0.2, 0.5, 0.9])
    b = np.array([0.5, 0.45, 0.1])
    c1 = (0.01 * data_range) ** 2
    expected = np.mean((2 * a * b + c1) / (a**2 + b**2 + c1))
    image_a = np.broadcast_to(a, (9, 11, 3)).copy()
    image_b = np.broadcast_to(b, (9, 11, 3)).copy()
    assert ssim(image_a, image_b, data_range=data_range) == pytest.approx(expected, rel=1e-9)
    assert compute_metric("ssim", image_a, image_b) == pytest.approx(
        np.mean((2 * a * b + 1e-4) / (a**2 + b**2 + 1e-4)), rel=1e-9)


def test_ssim_is_symmetric_and_works_on_images_smaller_than_its_window():
    other = np.clip(IMAGE + 0.1 * RNG.random(IMAGE.shape), 0, 1)
    assert ssim(IMAGE, other) == pytest.approx(ssim(other, IMAGE), abs=1e-12)
    small = IMAGE[:5, :4]
    assert ssim(small, small) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="at least 3 pixels"):
        ssim(IMAGE[:2], IMAGE[:2])


@pytest.mark.parametrize("pair, lab1, lab2, expected", SHARMA_2005, ids=[f"pair{p[0]}" for p in SHARMA_2005])
def test_ciede2000_reproduces_sharma_2005_through_the_rgb_path(pair, lab1, lab2, expected):
    image_true = lab_to_linear_rgb([[lab1]])
    image_test = lab_to_linear_rgb([[lab2]])
    assert ciede2000_map(image_true, image_test)[0, 0] == pytest.approx(expected, abs=5e-5)


def test_lab_conversion_matches_published_srgb_values():
    # linear grey 0.18: Y = 0.18, L* = 116 * 0.18^(1/3) - 16 (CIE 1976)
    grey = linear_rgb_to_lab([[[0.18, 0.18, 0.18]]])[0, 0]
    assert grey[0] == pytest.approx(116 * 0.18 ** (1 / 3) - 16, abs=1e-3)
    assert np.abs(grey[1:]).max() < 0.01
    # sRGB red primary in CIELAB (D65): L* 53.24, a* 80.09, b* 67.20 (Lindbloom's calculator)
    red = linear_rgb_to_lab([[[1.0, 0.0, 0.0]]])[0, 0]
    np.testing.assert_allclose(red, [53.24, 80.09, 67.20], atol=0.05)


def test_ciede2000_mean_and_p95_summarise_the_pixel_map():
    # 10% of the pixels carry Sharma pair 25's difference, the rest none
    _, lab1, lab2, expected = SHARMA_2005[8]
    image_true = np.broadcast_to(lab_to_linear_rgb(lab1), (20, 20, 3)).copy()
    image_test = image_true.copy()
    image_test[:2] = lab_to_linear_rgb(lab2)
    assert ciede2000_mean(image_true, image_test) == pytest.approx(0.1 * expected, abs=1e-4)
    assert ciede2000_p95(image_true, image_test) == pytest.approx(expected, abs=1e-4)


def test_flip_encodes_linear_input_to_srgb_itself():
    import flip_evaluator

    other = np.clip(IMAGE + RNG.normal(0, 0.1, IMAGE.shape), 0, 1)
    _, expected, _ = flip_evaluator.evaluate(
        srgb_encode(IMAGE), srgb_encode(other), "LDR", inputsRGB=True, applyMagma=False
    )
    assert flip(IMAGE, other) == pytest.approx(expected, rel=1e-5)
    assert flip(np.zeros_like(IMAGE), np.ones_like(IMAGE)) > 0.9


def test_edge_rmse_measures_only_the_masked_pixels():
    other = IMAGE.copy()
    other[MASK] += 0.2
    other[~MASK] += 1.0  # ignored
    assert edge_rmse(IMAGE, other, mask=MASK) == pytest.approx(0.2, rel=1e-12)
    assert math.isnan(edge_rmse(IMAGE, other, mask=np.zeros_like(MASK)))
    with pytest.raises(ValueError, match="mask has shape"):
        edge_rmse(IMAGE, other, mask=MASK[:-1])
    with pytest.raises(ValueError, match="boolean"):
        edge_rmse(IMAGE, other, mask=MASK.astype(int))


def crossed_pixels(outline, width, height) -> np.ndarray:
    """Pixels whose open interior the polygon's outline passes through (GEOS via shapely)."""
    from shapely.geometry import Polygon as ShapelyPolygon, box

    boundary = ShapelyPolygon(outline).boundary
    crossed = np.zeros((height, width), dtype=bool)
    for r in range(height):
        for c in range(width):
            pixel = box(c, r, c + 1, r + 1)
            inside = boundary.intersection(pixel).length - boundary.intersection(pixel.boundary).length
            crossed[r, c] = inside > 1e-9
    return crossed


@pytest.mark.parametrize(
    "outline",
    [
        # concave, reaching beyond the image, one edge on the pixel border x = 3
        [(3.0, 1.25), (3.0, 9.5), (7.4, 6.1), (11.7, 10.3), (13.9, -2.2), (8.2, 3.3)],
        # a thin sliver and a vertex inside a pixel
        [(1.1, 1.1), (14.6, 2.05), (1.3, 1.9)],
    ],
)
def test_edge_mask_is_the_pixels_the_outline_crosses(outline):
    width, height = 16, 12
    scene = parse_scene(
        {
            "image": {"width": width, "height": height},
            "polygons": [{"color": [1, 1, 1], "vertices": [[x, y, 1.0] for x, y in outline]}],
        }
    )
    expected = crossed_pixels(outline, width, height)
    assert expected.any() and not expected.all()
    np.testing.assert_array_equal(edge_mask(scene), expected)


def test_edge_mask_leaves_hidden_edges_out():
    # a small square entirely behind a big one: its outline is hidden
    scene = parse_scene(
        {
            "image": {"width": 8, "height": 8},
            "polygons": [
                {"color": [1, 0, 0], "vertices": [[2.5, 2.5, 5], [5.5, 2.5, 5], [5.5, 5.5, 5], [2.5, 5.5, 5]]},
                {"color": [0, 1, 0], "vertices": [[-1, -1, 1], [9, -1, 1], [9, 9, 1], [-1, 9, 1]]},
            ],
        }
    )
    assert not edge_mask(scene).any()


def test_flicker_of_a_static_error_is_zero():
    frames = RNG.random((5, 6, 7, 3))
    offset = RNG.normal(0, 0.3, (6, 7, 3))
    assert flicker(frames, frames + offset) == pytest.approx(0.0, abs=1e-12)


def test_flicker_of_an_alternating_error_is_its_amplitude():
    frames = RNG.random((6, 4, 5, 3))
    d = 0.07
    sign = np.array([1, -1, 1, -1, 1, -1], dtype=float)[:, None, None, None]
    assert flicker(frames, frames + d * sign) == pytest.approx(d, rel=1e-12)
    # half the pixels alternate with amplitude d, the rest keep still: RMS = d / sqrt(2)
    half = np.zeros((4, 5, 3))
    half[:2] = d
    assert flicker(frames, frames + sign * half) == pytest.approx(d / math.sqrt(2), rel=1e-12)


def test_flicker_checks_its_frames():
    frames = RNG.random((3, 4, 5, 3))
    with pytest.raises(ValueError, match="differ in shape"):
        flicker(frames, frames[:2])
    with pytest.raises(ValueError, match=r"\(F, H, W, 3\)"):
        flicker(frames[0], frames[0])


def test_dispatcher_routes_options_to_the_metrics_that_take_them():
    other = IMAGE + 0.1
    assert compute_metric("psnr", IMAGE, other, data_range=2.0, mask=MASK) == pytest.approx(
        psnr(IMAGE, other, data_range=2.0)
    )
    assert compute_metric("rmse", IMAGE, other, mask=MASK, data_range=2.0) == pytest.approx(0.1)
    assert compute_temporal_metric("flicker", IMAGE[None], other[None]) == 0.0
    assert set(TEMPORAL_METRICS) == {n for n, m in METRICS.items() if m.kind == "temporal"}
    assert {"flicker", "sum_variation"} <= set(TEMPORAL_METRICS)


def test_dispatcher_refuses_unknown_names_and_options():
    with pytest.raises(MetricError, match="unknown image metric 'psnrr'; available: rmse, psnr"):
        compute_metric("psnrr", IMAGE, IMAGE)
    with pytest.raises(MetricError, match=r"unknown image metric option\(s\) \['maks'\]"):
        compute_metric("rmse", IMAGE, IMAGE, maks=MASK)
    with pytest.raises(MetricError, match=r"'edge_rmse' needs option\(s\) \['mask'\]"):
        compute_metric("edge_rmse", IMAGE, IMAGE)
    with pytest.raises(MetricError, match="unknown temporal metric"):
        compute_temporal_metric("rmse", IMAGE[None], IMAGE[None])


@pytest.mark.parametrize("metric, option", [(psnr, "data_range"), (ssim, "data_range"), (flip, "ppd")])
@pytest.mark.parametrize("value", [0.0, -1.0, float("nan")])
def test_non_positive_options_are_refused(metric, option, value):
    with pytest.raises(ValueError, match=f"{option} must be positive"):
        metric(IMAGE, IMAGE, **{option: value})


def test_bias_and_flicker_split_the_error_of_an_animation():
    from aaeval.metrics import temporal_bias

    rng = np.random.default_rng(3)
    truth = rng.random((5, 6, 7, 3))
    steady = rng.normal(0, 0.1, (6, 7, 3))
    wobble = rng.normal(0, 0.05, (5, 6, 7, 3))
    test = truth + steady + wobble - wobble.mean(axis=0)
    assert temporal_bias(truth, truth + steady) == pytest.approx(np.sqrt(np.mean(steady**2)))
    assert flicker(truth, truth + steady) == pytest.approx(0.0, abs=1e-15)
    mse = np.mean((test - truth) ** 2)
    assert temporal_bias(truth, test) ** 2 + flicker(truth, test) ** 2 == pytest.approx(mse)


def test_highlight_bias_is_the_time_average_and_energy_flicker_what_is_left():
    from aaeval.metrics import highlight_bias, highlight_energy_flicker

    truth = np.ones((4, 3, 3))
    mask = np.zeros((3, 3), bool)
    mask[1, 1] = True
    scale = np.array([0.5, 0.5, 0.5, 0.5])[:, None, None]
    dim = truth * scale  # steadily half as bright: bias, no flicker
    assert highlight_bias(truth, dim, mask=mask) == pytest.approx(-0.5)
    assert highlight_energy_flicker(truth, dim, mask=mask) == pytest.approx(0.0)
    pops = truth * np.array([1.2, 0.8, 1.2, 0.8])[:, None, None]  # no bias, flicker 0.2
    assert highlight_bias(truth, pops, mask=mask) == pytest.approx(0.0, abs=1e-12)
    assert highlight_energy_flicker(truth, pops, mask=mask) == pytest.approx(0.2)


def test_image_flicker_measures_the_test_alone_inside_the_mask():
    from aaeval.metrics import image_flicker

    frames = np.zeros((4, 3, 4, 3))
    frames[:, :, 0] = np.array([0.0, 1.0, 0.0, 1.0])[:, None, None]  # column 0 blinks by +-0.5
    inside = np.zeros((3, 4), bool)
    inside[:, 0] = True
    assert image_flicker(frames * 0, frames, mask=inside) == pytest.approx(0.5)
    assert image_flicker(frames * 0, frames, mask=~inside) == 0.0
    assert math.isnan(image_flicker(frames, frames, mask=np.zeros((3, 4), bool)))


def test_a_measured_frame_evaluates_flip_once_for_its_metric_and_its_map(monkeypatch):
    """A sweep cell takes FLIP's mean as the ``flip`` metric and its map for the viewer: one
    evaluation gives both, with the values two separate calls give; ``aaeval compare`` keeps
    no map and asks for none."""
    import flip_evaluator

    from aaeval.sweeps.measure import measure_frame
    from aaeval.metrics.perceptual import flip, flip_map
    from aaeval.renderers import MethodSpec, render
    from aaeval.scenes.generate import random_triangles

    scene = random_triangles(50, 64, 64, size=20.0, seed=1)
    reference, image = render(scene, "catmull"), render(scene, "supersample:k=2")
    calls = []
    evaluate = flip_evaluator.evaluate
    monkeypatch.setattr(flip_evaluator, "evaluate", lambda *a, **k: calls.append(1) or evaluate(*a, **k))
    spec = MethodSpec.parse("supersample:k=2")
    measured = measure_frame(scene, spec, 0, reference, ["rmse", "flip"], digest="flip-once")
    assert len(calls) == 1
    assert measured.metrics["flip"] == flip(reference, image)
    assert np.array_equal(measured.flip, flip_map(reference, image))
    calls.clear()
    assert measure_frame(scene, spec, 0, reference, ["rmse"], digest="flip-once", keep_flip=False).flip is None
    assert calls == []


def test_a_measured_frame_computes_one_ciede2000_map_for_its_mean_and_p95(monkeypatch):
    """``ciede2000_mean`` and ``ciede2000_p95`` of a sweep cell read one CIEDE2000 map: one
    colour difference per cell, and the values of the metrics called alone."""
    import colour

    from aaeval.sweeps.measure import measure_frame
    from aaeval.renderers import MethodSpec, render
    from aaeval.scenes.generate import random_triangles

    scene = random_triangles(30, 24, 24, size=8.0, seed=2)
    reference, image = render(scene, "catmull"), render(scene, "point")
    calls = []
    delta_e = colour.delta_E
    monkeypatch.setattr(colour, "delta_E", lambda *a, **k: calls.append(1) or delta_e(*a, **k))
    measured = measure_frame(scene, MethodSpec.parse("point"), 0, reference, ["ciede2000_mean", "ciede2000_p95"],
                             digest="ciede-once", keep_flip=False)
    assert len(calls) == 1
    assert measured.metrics["ciede2000_mean"] == ciede2000_mean(reference, image) > 0
    assert measured.metrics["ciede2000_p95"] == ciede2000_p95(reference, image) > 0
    assert len(calls) == 3  # outside a cell each call computes its own map


def test_flip_on_one_thread_gives_every_pixel_the_value_of_flip_on_many():
    """FLIP runs on one OpenMP thread (a sweep gives each core its own worker); each pixel's
    error is computed alone, so the map is the one FLIP's own team of threads gives, bit for
    bit, and the mean the same to float rounding."""
    import flip_evaluator
    from threadpoolctl import threadpool_limits

    from aaeval.metrics.perceptual import flip_map

    rng = np.random.default_rng(5)
    true = rng.random((61, 47, 3))
    test = np.clip(true + 0.2 * rng.standard_normal(true.shape), 0.0, 1.0)
    with threadpool_limits(limits=4, user_api="openmp"):
        expected, mean, _ = flip_evaluator.evaluate(true, test, "LDR", inputsRGB=False, applyMagma=False,
                                                    computeMeanError=True, parameters={})
    assert np.array_equal(flip_map(true, test), expected.reshape(true.shape[:2]))
    assert flip(true, test) == pytest.approx(mean, rel=1e-6)


def test_ciede2000_maps_in_bulk_are_the_maps_of_one_call_per_pair():
    """The CIEDE2000 maps of many pairs computed together are each pair's own, bit for bit
    (every step is per pixel), and kept only inside maps_once_per_pair."""
    from aaeval.metrics._pairs import maps_once_per_pair
    from aaeval.metrics.colour_difference import ciede2000_maps

    rng = np.random.default_rng(7)
    pairs = [(rng.random((9, 13, 3)), rng.random((9, 13, 3)) * 1.3) for _ in range(5)] + [
        (rng.random((4, 6, 3)), rng.random((4, 6, 3))) for _ in range(2)]
    alone = [ciede2000_map(a, b) for a, b in pairs]
    with maps_once_per_pair():
        ciede2000_maps(pairs)
        for (a, b), expected in zip(pairs, alone):
            assert np.array_equal(ciede2000_map(a, b), expected)
            assert ciede2000_map(a, b) is ciede2000_map(a, b)  # kept, not computed again


def test_maps_once_per_pair_belongs_to_the_thread_that_entered_it():
    """Cells measured at once on threads of one process (a Dask worker's threads) keep their
    own maps: a thread leaving its block neither ends another's nor sees its pairs."""
    import threading

    from aaeval.metrics._pairs import maps_once_per_pair

    rng = np.random.default_rng(11)
    pairs = [(rng.random((6, 7, 3)), rng.random((6, 7, 3))) for _ in range(8)]
    expected = [ciede2000_map(a, b) for a, b in pairs]
    errors, barrier = [], threading.Barrier(len(pairs))

    def cell(k):
        try:
            a, b = pairs[k]
            with maps_once_per_pair():
                first = ciede2000_map(a, b)
                barrier.wait(timeout=30)  # every thread inside its block at once
                if k % 2:  # half leave at once while the others still read theirs
                    return
                assert ciede2000_map(a, b) is first and np.array_equal(first, expected[k])
        except Exception as exc:  # noqa: BLE001 - reported below, in the test's thread
            errors.append(repr(exc))

    threads = [threading.Thread(target=cell, args=(k,)) for k in range(len(pairs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert ciede2000_map(*pairs[0]) is not ciede2000_map(*pairs[0])  # outside every block: computed each time


def test_a_chunk_of_frames_measures_what_each_frame_measures_alone(monkeypatch):
    """measure_frames on a chunk (the sweep's task): the metrics of each frame measured
    alone, the CIEDE2000 maps of the chunk in one colour difference."""
    import colour

    from aaeval.sweeps.measure import FrameJob, measure_frame, measure_frames
    from aaeval.renderers import MethodSpec, render
    from aaeval.scenes.generate import random_triangles

    metrics = ["rmse", "ssim", "ciede2000_mean", "ciede2000_p95", "flip"]
    scenes = [random_triangles(20, 16, 16, size=6.0, seed=s) for s in range(4)]
    spec = MethodSpec.parse("supersample:k=2")
    jobs = [FrameJob(scene, spec, 0, render(scene, "catmull"), metrics, digest=f"chunk-{i}")
            for i, scene in enumerate(scenes)]
    alone = [measure_frame(job.scene, spec, 0, job.reference, metrics, digest=job.digest) for job in jobs]
    calls = []
    delta_e = colour.delta_E
    monkeypatch.setattr(colour, "delta_E", lambda *a, **k: calls.append(1) or delta_e(*a, **k))
    together = measure_frames(jobs)
    assert len(calls) == 1
    for one, chunk in zip(alone, together):
        assert chunk.error is None and chunk.metrics == one.metrics and np.array_equal(chunk.flip, one.flip)
