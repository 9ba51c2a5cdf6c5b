"""The native Weiler-Atherton kernels (aaeval.native.weiler_atherton) refuse bad inputs at the
binding with a one-line ValueError instead of reading out of bounds."""

from __future__ import annotations

import numpy as np
import pytest

import aaeval.native.weiler_atherton as wa
import aaeval.native.weiler_atherton_testing as wa_testing

SQ = (np.array([0.0, 2.0, 2.0, 0.0]), np.array([0.0, 0.0, 2.0, 2.0]), np.zeros(4, np.int64), np.array([0, 4]))
TRI = (np.array([1.0, 3.0, 1.0]), np.array([1.0, 1.0, 3.0]), np.ones(3, np.int64), np.array([0, 3]))


def raises_one_line(call, match):
    with pytest.raises(ValueError, match=match) as err:
        call()
    assert "\n" not in str(err.value)


def with_(shape, k, value):
    out = list(shape)
    out[k] = value
    return tuple(out)


@pytest.mark.parametrize("bad, match", [
    (with_(SQ, 0, SQ[0].astype(np.float32)), "float64"),
    (with_(SQ, 0, np.zeros((4, 2))), "dimension"),
    (with_(SQ, 0, np.zeros(8)[::2]), "C-contiguous"),
    (with_(SQ, 1, np.zeros(3)), "entries"),
    (with_(SQ, 2, np.zeros(4, np.int32)), "int64"),
    (with_(SQ, 3, np.array([0, 5])), "must end at"),
    (with_(SQ, 3, np.array([1, 4])), "start at 0"),
    (with_(SQ, 3, np.array([0, 3, 2, 4])), "contour 1"),
    (with_(SQ, 0, np.array([0.0, np.nan, 2.0, 0.0])), "finite"),
    (with_(SQ, 1, np.array([0.0, np.inf, 2.0, 0.0])), "finite"),
])
def test_clip_arrays_refuses_inconsistent_shapes(bad, match):
    raises_one_line(lambda: wa.clip_arrays(*bad, *TRI, 1e-12), match)
    raises_one_line(lambda: wa.clip_arrays(*TRI, *bad, 1e-12), match)


def test_clip_arrays_refuses_a_nan_tolerance_and_answers_on_good_input():
    raises_one_line(lambda: wa.clip_arrays(*SQ, *TRI, float("nan")), "eps")
    ix, iy, il, ist, ox, oy, ol, ost = wa.clip_arrays(*SQ, *TRI, 1e-12)
    assert wa.ring_area_of(ix, iy, 0, len(ix)) == pytest.approx(0.5 * 1 + 1.0 + 0.0 * 0, abs=1.0)
    assert len(ist) == 2 and len(ost) == 2


def test_solver_and_helpers_refuse_indices_out_of_range():
    boxes = np.array([[0.0, 0.0, 2.0, 2.0]])
    raises_one_line(lambda: wa.later_neighbours(boxes, np.array([0, 1])), "index below 1")
    raises_one_line(lambda: wa.later_neighbours(boxes[:, :3].copy(), np.array([0])), "axis 1")
    raises_one_line(lambda: wa.ring_area_of(SQ[0], SQ[1], 0, 9), "vertex range")
    vertices = np.array([[0.0, 0, 1], [2, 0, 1], [2, 2, 1]])
    planes = np.array([[0.0, 0.0, 1.0]])
    raises_one_line(lambda: wa.originals(vertices, np.array([1]), np.array([3]), planes), "range")
    raises_one_line(lambda: wa.originals(vertices, np.array([0]), np.array([0]), planes), "range")
    raises_one_line(lambda: wa.originals(vertices, np.array([0]), np.array([3]), np.zeros((2, 3))), "entries")
    ox, oy, ost, obb, zmin, scale, zmax = wa.originals(vertices, np.array([0]), np.array([3]), planes)
    win = (0.0, 0.0, 4.0, 4.0)
    raises_one_line(lambda: wa.solve_window(ox, oy, ost, obb, planes, np.array([1]), win, 1e-13, 1e-11), "index below")
    raises_one_line(lambda: wa.solve_window(ox, oy, ost[:1].copy(), obb, planes, np.array([0]), win, 1e-13, 1e-11), "end at")
    raises_one_line(lambda: wa.solve_window(ox, oy, ost, obb, planes, np.array([0]), (0.0, 0.0, np.nan, 4.0), 1e-13, 1e-11),
            "window")
    xs, ys, labels, starts, piece_rings, sources = wa.solve_window(ox, oy, ost, obb, planes, np.array([0]), win,
                                                                   1e-13, 1e-11)
    assert sources.tolist() == [0] and wa.ring_area_of(xs, ys, 0, len(xs)) == 2.0


def test_add_coverage_refuses_mismatched_weights_and_output():
    xs, ys, _, starts = SQ
    out = np.zeros((3, 3, 2))
    raises_one_line(lambda: wa.add_coverage(xs, ys, starts, np.ones((1, 3)), out), "axis 1")
    raises_one_line(lambda: wa.add_coverage(xs, ys, starts, np.ones((2, 2)), out), "axis 0")
    raises_one_line(lambda: wa.add_coverage(xs, ys, starts, np.ones((1, 2)), np.zeros((3, 3))), "dimension")
    raises_one_line(lambda: wa.add_coverage(xs, ys, np.array([0, 2]), np.ones((1, 2)), out), "must end at")
    wa.add_coverage(xs, ys, starts, np.ones((1, 2)), out)
    assert out[..., 0].sum() == 4.0 and out[0, 0, 1] == 1.0


def test_coverage_over_is_add_coverage_on_an_image_filled_with_its_base():
    """Bit for bit, on random rings reaching past every side of the image (and holes: rings
    wound negative), with the refusals of add_coverage and its own for the base."""
    rng = np.random.default_rng(5)
    for _ in range(40):
        h, w, k = int(rng.integers(1, 12)), int(rng.integers(1, 12)), int(rng.integers(1, 4))
        lengths = rng.integers(3, 9, int(rng.integers(1, 6)))
        starts = np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64)
        xs, ys = rng.uniform(-3, w + 3, starts[-1]), rng.uniform(-3, h + 3, starts[-1])
        weights, base = rng.normal(size=(len(lengths), k)), rng.normal(size=k)
        filled = np.empty((h, w, k))
        filled[:] = base
        wa.add_coverage(xs, ys, starts, weights, filled)
        image = wa.coverage_over(xs, ys, starts, weights, base, h, w)
        assert image.shape == (h, w, k) and image.tobytes() == filled.tobytes()
    xs, ys, _, starts = SQ
    raises_one_line(lambda: wa.coverage_over(xs, ys, starts, np.ones((1, 3)), np.zeros(2), 3, 3), "axis 1")
    raises_one_line(lambda: wa.coverage_over(xs, ys, starts, np.ones((1, 2)), np.zeros((1, 2)), 3, 3), "dimension")
    raises_one_line(lambda: wa.coverage_over(xs, ys, starts, np.ones((1, 0)), np.zeros(0), 3, 3), "one channel")
    raises_one_line(lambda: wa.coverage_over(xs, ys, starts, np.ones((1, 2)), np.zeros(2), -1, 3), "image size")
    raises_one_line(lambda: wa.coverage_over(xs, ys, np.array([0, 2]), np.ones((1, 2)), np.zeros(2), 3, 3), "must end at")


def test_split_convex_refuses_rows_too_short():
    xs, ys, labels, _ = SQ
    d = np.array([-1.0, 1.0, 1.0, -1.0])
    short = [np.zeros(2), np.zeros(2), np.zeros(2, np.int64), np.zeros(2), np.zeros(2), np.zeros(2, np.int64)]
    raises_one_line(lambda: wa_testing.split_convex(xs, ys, labels, 4, d, 1e-12, 9, *short), "too short")
    raises_one_line(lambda: wa_testing.split_convex(xs, ys, labels, 5, d, 1e-12, 9, *short), "fewer than n")
    raises_one_line(lambda: wa_testing.vertex_sides(d, 7, 0.0), "fewer than n")


def test_components_labels_each_node_with_its_smallest():
    assert wa.components(5, np.array([3, 1]), np.array([4, 3])).tolist() == [0, 1, 2, 1, 1]
    raises_one_line(lambda: wa.components(2, np.array([0]), np.array([2])), "index below")


def hostile_calls(seed: int, count: int):
    """``count`` random calls of the bindings, half of them with inconsistent arrays (wrong
    dtypes, shapes, strides, lengths, starts, indices, non-finite values): each a thunk."""
    rng = np.random.default_rng(seed)

    def arr(n, kind):
        r = rng.random()
        if r < 0.05:
            return np.zeros(n, np.float32 if kind == "f" else np.int32)
        if r < 0.08:
            return np.zeros((n, 2))
        if r < 0.1:
            return np.zeros(2 * n + 1)[::2] if kind == "f" else np.zeros(2 * n + 1, np.int64)[::2]
        if kind == "i":
            return rng.integers(-2, n + 3, n).astype(np.int64)
        v = [rng.uniform(-5, 5, n), rng.integers(-3, 4, n).astype(float), rng.normal(size=n) * 1e8,
             np.full(n, 1.0)][int(rng.integers(4))]
        if rng.random() < 0.05 and n:
            v[rng.integers(n)] = rng.choice([np.nan, np.inf, 1e300, -1e300, 5e-324])
        return v

    def starts(n):
        if rng.random() < 0.7:
            cuts = np.sort(rng.integers(0, n + 1, int(rng.integers(0, 4))))
            return np.concatenate([[0], cuts, [n]]).astype(np.int64)
        return rng.integers(-1, n + 2, int(rng.integers(0, 5))).astype(np.int64)

    def shape():
        n = int(rng.integers(0, 12))
        return (arr(n, "f"), arr(n + (rng.random() < 0.05), "f"),
                rng.integers(0, 3, n + (rng.random() < 0.05)).astype(np.int64), starts(n))

    for _ in range(count):
        f = int(rng.integers(0, 6))
        if f == 0:
            a, b, eps = shape(), shape(), float(rng.choice([1e-12, 0.0, 0.3, np.inf, -1.0, np.nan]))
            yield lambda a=a, b=b, eps=eps: wa.clip_arrays(*a, *b, eps)
        elif f == 1:
            s = shape()
            yield lambda s=s: wa.first_crossing(s[0], s[1], s[3], 1e-12)
        elif f == 2:
            n = int(rng.integers(0, 8))
            bx = rng.uniform(0, 10, (n, 4))
            bx[:, 2:] += bx[:, :2]
            bx = bx if rng.random() < 0.9 else bx[:, :3].copy()
            order = arr(int(rng.integers(0, 10)), "i")
            yield lambda bx=bx, order=order: wa.later_neighbours(bx, order)
        elif f == 3:
            npoly, nv = int(rng.integers(1, 8)), int(rng.integers(0, 30))
            v = np.column_stack([rng.integers(-2, 12, nv).astype(float), rng.integers(-2, 12, nv).astype(float),
                                 rng.uniform(0, 5, nv)])
            st, ln = rng.integers(-1, nv + 1, npoly).astype(np.int64), rng.integers(0, 6, npoly).astype(np.int64)
            pl = rng.normal(size=(npoly, 3))
            pl[rng.random(npoly) < 0.2] = np.nan
            win = tuple(rng.uniform(-2, 12, 4))
            eps, eps_z, road = float(rng.choice([1e-12, 0.0, 0.5])), float(rng.choice([1e-11, 0.0, 1.0])), rng.random() < 0.5
            bad_order = rng.integers(-1, npoly + 1, 3).astype(np.int64) if rng.random() < 0.1 else None
            rule = rng.random() < 0.3

            def solve(v=v, st=st, ln=ln, pl=pl, win=win, eps=eps, eps_z=eps_z, road=road, bad_order=bad_order,
                      rule=rule):
                ox, oy, ost, obb, _, _, _ = wa.originals(v, st, ln, pl)
                order = np.flatnonzero(np.diff(ost) > 0).astype(np.int64) if bad_order is None else bad_order
                if rule:
                    return wa.solve_by_rule(ox, oy, ost, obb, pl, order, win, eps, eps_z)
                return wa.solve_window(ox, oy, ost, obb, pl, order, win, eps, eps_z, bool(road))

            yield solve
        elif f == 4:
            s = shape()
            nr, k = max(len(s[3]) - 1, 0), int(rng.integers(0, 4))
            weights = rng.normal(size=(nr + (rng.random() < 0.05), k))
            out = np.zeros((int(rng.integers(0, 6)), int(rng.integers(0, 6)), k))
            if rng.random() < 0.5:
                yield lambda s=s, weights=weights, out=out: wa.add_coverage(s[0], s[1], s[3], weights, out)
            else:
                base = rng.normal(size=k + (rng.random() < 0.05))
                h, w = out.shape[0] - int(rng.random() < 0.05), out.shape[1]
                yield lambda s=s, weights=weights, base=base, h=h, w=w: wa.coverage_over(
                    s[0], s[1], s[3], weights, base, h, w)
        else:
            n = int(rng.integers(0, 8))
            m = int(rng.integers(0, 2 * n + 3))
            outs = [np.zeros(m), np.zeros(m), np.zeros(m, np.int64), np.zeros(m), np.zeros(m), np.zeros(m, np.int64)]
            args = (arr(n, "f"), arr(n, "f"), rng.integers(0, 3, n).astype(np.int64), int(rng.integers(-1, n + 2)),
                    rng.normal(size=n), float(rng.choice([1e-12, -1.0, 0.5])), 7, *outs)
            yield lambda args=args: wa_testing.split_convex(*args)


def test_hostile_inputs_are_answered_or_refused_with_a_value_error():
    """3000 random calls, many inconsistent: each answers or raises a one-line ValueError
    (the same corpus ran 60000 cases through an ASan + UBSan build without a report)."""
    answered = refused_count = 0
    for call in hostile_calls(seed=11, count=3000):
        try:
            call()
            answered += 1
        except ValueError as error:
            assert "\n" not in str(error)
            refused_count += 1
    assert answered > 500 and refused_count > 500


def test_solve_by_rule_refuses_bad_sources_and_answers_a_pair():
    xs = np.array([0.0, 4, 4, 0, 1, 5, 5, 1])
    ys = np.array([0.0, 0, 4, 4, 1, 1, 5, 5])
    starts = np.array([0, 4, 8])
    boxes = np.array([[0.0, 0, 4, 4], [1.0, 1, 5, 5]])
    planes = np.array([[0.0, 0, 1], [0.0, 0, 2]])
    win = (0.0, 0.0, 6.0, 6.0)
    raises_one_line(lambda: wa.solve_by_rule(xs, ys, starts, boxes, planes, np.array([0, 2]), win, 1e-13, 1e-11), "index below")
    raises_one_line(lambda: wa.solve_by_rule(xs, ys, starts, boxes[:1].copy(), planes, np.array([0]), win, 1e-13, 1e-11), "entries")
    regions = wa.solve_by_rule(xs, ys, starts, boxes, planes, np.array([0, 1]), win, 1e-13, 1e-11)
    areas = {s: wa.ring_area_of(x, y, 0, len(x)) if len(st) == 2 else None for s, x, y, _, st in regions}
    assert areas == {1: 7.0, 0: 16.0}  # the nearer square whole, the farther one less their overlap
