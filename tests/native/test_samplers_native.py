"""The native samplers' bindings (aaeval.native.samplers): bad inputs are one-line
ValueErrors, never a crash; the jitter hash and the depth rule are the documented ones;
a deep A-buffer stack is sorted in n log n with the insertion sort's order."""

from __future__ import annotations


import numpy as np
import pytest

from aaeval.native import samplers as _samplers
from aaeval.native import samplers_testing
from aaeval.filters import get_filter
from aaeval.filters.registry import profile_args
from aaeval.renderers import render
from aaeval.renderers.sampling import kernel_scene, warmup_scene
from aaeval.scenes import parse_scene
from aaeval.scenes.generate import coplanar_stack


def _args():
    return list(kernel_scene(warmup_scene()))


BOX = profile_args(get_filter("box"))
MITCHELL = profile_args(get_filter("mitchell"))


def _sample(args, k=2, jitter=False, seed=0, filt=BOX):
    return _samplers.sample_image(*args, k, jitter, seed, *filt)


def test_the_warm_up_scene_renders():
    args = _args()
    assert _sample(args).shape == (4, 5, 3)
    assert _samplers.abuffer_image(*args).shape == (4, 5, 3)
    assert np.isfinite(_sample(args, 3, True, 7, MITCHELL)).all()


def _with(i, value):
    args = _args()
    args[i] = value(args[i]) if callable(value) else value
    return args


BAD_SCENES = {
    "negative width": lambda: _with(0, -1),
    "huge image": lambda: _with(1, 1 << 40),
    "starts float": lambda: _with(2, lambda a: a.astype(float)),
    "starts 2-D": lambda: _with(2, lambda a: a[:, None]),
    "start out of range": lambda: _with(2, lambda a: a + 1000),
    "negative start": lambda: _with(2, lambda a: a - 100),
    "length too long": lambda: _with(3, lambda a: a * 1000),
    "negative length": lambda: _with(3, lambda a: -a),
    "lengths short": lambda: _with(3, lambda a: a[:-1]),
    "xs strided": lambda: _with(4, lambda a: np.repeat(a, 2)[::2]),
    "ys short": lambda: _with(5, lambda a: a[:-1]),
    "xs nan": lambda: _with(4, lambda a: np.where(np.arange(a.size) == 1, np.nan, a)),
    "ys inf": lambda: _with(5, lambda a: np.where(np.arange(a.size) == 0, np.inf, a)),
    "planes float32": lambda: _with(6, lambda a: a.astype(np.float32)),
    "planes transposed": lambda: _with(6, lambda a: np.ascontiguousarray(a.T).T),
    "planes nan": lambda: _with(6, lambda a: a * np.nan),
    "eps nan": lambda: _with(7, float("nan")),
    "colors short": lambda: _with(8, lambda a: a[:-1]),
    "background 4": lambda: _with(9, np.zeros(4)),
}


@pytest.mark.parametrize("case", sorted(BAD_SCENES))
def test_bad_scene_arrays_are_value_errors(case):
    args = BAD_SCENES[case]()
    with pytest.raises(ValueError) as info:
        _sample(args)
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError):
        _samplers.abuffer_image(*args)


@pytest.mark.parametrize("filt, k", [
    ((0, 0.5, np.zeros((1, 1)), 0.0, 0.0), 0),
    ((0, 0.5, np.zeros((1, 1)), 0.0, 0.0), 10**6),
    ((7, 0.5, np.zeros((1, 1)), 0.0, 0.0), 2),
    ((1, 2.0, np.zeros((1, 4)), 0.0, 0.0), 2),  # too few pieces for the radius
    ((1, 2.0, np.zeros((4, 0)), 0.0, 0.0), 2),
    ((1, float("inf"), np.zeros((4, 4)), 0.0, 0.0), 2),
    ((1, -1.0, np.zeros((4, 4)), 0.0, 0.0), 2),
    ((2, 2.0, np.zeros((1, 1)), float("nan"), 0.0), 2),
    ((1, 2.0, np.full((4, 4), np.nan), 0.0, 0.0), 2),
])
def test_bad_filters_and_sample_counts_are_value_errors(filt, k):
    with pytest.raises(ValueError):
        _sample(_args(), k, False, 0, filt)


def test_non_arrays_are_refused():
    args = _args()
    args[4] = [0.0, 1.0]
    with pytest.raises((TypeError, ValueError)):
        _sample(args)


def test_jitter_is_splitmix64_of_seed_row_column_sample_axis():
    def splitmix(z):
        z = (z + 0x9E3779B97F4A7C15) % 2**64
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) % 2**64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) % 2**64
        return z ^ (z >> 31)

    for seed, row, col, s, axis in [(0, 0, 0, 0, 0), (7, 3, 11, 5, 1), (2**62, 9, 1, 15, 0)]:
        h = splitmix(seed)
        for v in (row, col, 2 * s + axis):
            h = splitmix(h ^ v)
        assert samplers_testing.jitter_uniform(seed, row, col, s, axis) == (h >> 11) / 2.0**53


def test_tied_latest_first_puts_the_latest_of_a_run_first():
    depth = np.array([0.0, 0.8, 1.6, 5.0, 5.0])
    index = np.arange(5, dtype=np.int64)
    order = np.lexsort((-index, depth)).astype(np.int64)
    assert _samplers.tied_latest_first(order, depth, index, 1.0).tolist() == [1, 0, 2, 4, 3]
    with pytest.raises(ValueError):
        _samplers.tied_latest_first(order + 5, depth, index, 1.0)
    with pytest.raises(ValueError):
        _samplers.tied_latest_first(order, depth, index[:-1], 1.0)


def test_a_deep_abuffer_stack_shows_the_latest_tied_polygon():
    # 3000 coplanar triangles over one 12 x 12 image, each pixel's fragments in the worst
    # order for an insertion sort (4.5 million moves a pixel); the merge sort gives the same
    # order (distinct keys), and the tie rule's latest polygon is seen everywhere (its time
    # is benchmarks/bench_baselines.py's deep-stack line, not asserted here)
    n = 3000
    image = render(coplanar_stack(n), "abuffer")
    np.testing.assert_array_equal(image[..., 0], (n - 1) / n)


def test_jitter_seeds_are_64_bit():
    from aaeval.renderers.sampling import point_sampled

    scene = warmup_scene()
    assert np.array_equal(point_sampled(scene, 2, seed=2**64 - 1), point_sampled(scene, 2, seed=-1))
    assert not np.array_equal(point_sampled(scene, 2, seed=2**63), point_sampled(scene, 2, seed=0))
    with pytest.raises(ValueError):
        point_sampled(scene, 2, seed=2**64)


@pytest.mark.parametrize("seed", range(4))
def test_random_and_extreme_inputs_give_an_image_or_a_value_error(seed):
    # pixel-boundary and huge coordinates (1e15: crossings far outside the image; 1e300 and
    # zero-length polygons: refused, as every family's polygon check refuses them), ties,
    # eps of 0 and 1e300; run under scripts/fuzz_native.sh's sanitized build this checks
    # every access
    rng = np.random.default_rng(seed)
    filters = [BOX, MITCHELL, profile_args(get_filter("gaussian")), profile_args(get_filter("tent"))]
    for case in range(150):
        w, h, n = (int(v) for v in rng.integers(0, 10, 3))
        lengths = rng.integers(0 if case % 7 == 0 else 3, 8, n).astype(np.int64)
        starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)[:n]
        scale = [1.0, 1e-9, 1e15, 1e300][case % 4]
        xs = rng.uniform(-0.5, 1.5, lengths.sum()) * max(w, 1) * (scale if case % 3 == 0 else 1.0)
        ys = rng.uniform(-0.5, 1.5, lengths.sum()) * max(h, 1) * (scale if case % 3 == 1 else 1.0)
        if case % 5 == 0:
            xs, ys = np.round(xs * 2) / 2, np.round(ys * 2) / 2
        planes = rng.normal(size=(n, 3)) * (scale if case % 4 == 0 else 1.0)
        args = (w, h, starts, lengths, xs, ys, planes, float(rng.choice([0.0, 1e-11, 1e300])),
                rng.uniform(0, 1, (n, 3)), rng.uniform(0, 1, 3))
        for run in (lambda: _samplers.sample_image(*args, int(rng.integers(1, 5)), bool(case % 2), case,
                                                   *filters[case % len(filters)]),
                    lambda: _samplers.abuffer_image(*args)):
            try:
                image = run()
            except (ValueError, ZeroDivisionError):
                continue
            assert image.shape == (h, w, 3)
        m = int(rng.integers(1, 30))
        pts = (rng.integers(0, 4, (m, 2)) if case % 2 else rng.normal(size=(m, 2))) * scale
        a = np.arange(m, dtype=np.int64)
        b = np.roll(a, -1)
        try:
            e, f = _samplers.sweep(pts, a, b, np.lexsort((pts[:, 1], pts[:, 0])).astype(np.int64), np.roll(a, 1))
        except ValueError:
            continue
        assert -1 <= e < m and -1 <= f < m


def test_the_native_profile_is_the_filters_profile():
    # the splat weight the samplers use, bound as profile_array: the same bits as
    # aaeval.filters.evaluate's, so that module can take it instead of a Python loop
    from aaeval.filters import FILTERS
    from aaeval.filters import evaluate

    t = np.concatenate([np.linspace(-5, 5, 20001), np.random.default_rng(0).uniform(-4, 4, 20000),
                        [np.inf, -np.inf, 0.5, -0.5, 2.0, -2.0, 1.5, -1.5, -0.0]])
    for name in FILTERS:
        args = profile_args(get_filter(name))
        native = _samplers.profile_array(*args, t)
        if hasattr(evaluate, "profile_array") and evaluate.profile_array is not _samplers.profile_array:
            assert native.tobytes() == evaluate.profile_array(*args, t).tobytes(), name
        assert np.all(native[np.abs(t) > max(args[1], 0.5)] == 0.0), name
    with pytest.raises(ValueError):
        _samplers.profile_array(*BOX, np.array([np.nan]))
