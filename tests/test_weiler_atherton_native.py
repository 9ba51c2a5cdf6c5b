"""The native Weiler-Atherton kernels (aaeval._weiler_atherton) refuse bad inputs at the
binding with a one-line ValueError instead of reading out of bounds (issue 20)."""

from __future__ import annotations

import numpy as np
import pytest

import aaeval._weiler_atherton as wa

SQ = (np.array([0.0, 2.0, 2.0, 0.0]), np.array([0.0, 0.0, 2.0, 2.0]), np.zeros(4, np.int64), np.array([0, 4]))
TRI = (np.array([1.0, 3.0, 1.0]), np.array([1.0, 1.0, 3.0]), np.ones(3, np.int64), np.array([0, 3]))


def refused(call, match):
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
    refused(lambda: wa.clip_arrays(*bad, *TRI, 1e-12), match)
    refused(lambda: wa.clip_arrays(*TRI, *bad, 1e-12), match)


def test_clip_arrays_refuses_a_nan_tolerance_and_answers_on_good_input():
    refused(lambda: wa.clip_arrays(*SQ, *TRI, float("nan")), "eps")
    ix, iy, il, ist, ox, oy, ol, ost = wa.clip_arrays(*SQ, *TRI, 1e-12)
    assert wa.ring_area_of(ix, iy, 0, len(ix)) == pytest.approx(0.5 * 1 + 1.0 + 0.0 * 0, abs=1.0)
    assert len(ist) == 2 and len(ost) == 2


def test_solver_and_helpers_refuse_indices_out_of_range():
    boxes = np.array([[0.0, 0.0, 2.0, 2.0]])
    refused(lambda: wa.later_neighbours(boxes, np.array([0, 1])), "index below 1")
    refused(lambda: wa.later_neighbours(boxes[:, :3].copy(), np.array([0])), "axis 1")
    refused(lambda: wa.ring_area_of(SQ[0], SQ[1], 0, 9), "vertex range")
    vertices = np.array([[0.0, 0, 1], [2, 0, 1], [2, 2, 1]])
    planes = np.array([[0.0, 0.0, 1.0]])
    refused(lambda: wa.originals(vertices, np.array([1]), np.array([3]), planes), "range")
    refused(lambda: wa.originals(vertices, np.array([0]), np.array([0]), planes), "range")
    refused(lambda: wa.originals(vertices, np.array([0]), np.array([3]), np.zeros((2, 3))), "entries")
    ox, oy, ost, obb, zmin, scale, zmax = wa.originals(vertices, np.array([0]), np.array([3]), planes)
    win = (0.0, 0.0, 4.0, 4.0)
    refused(lambda: wa.solve_window(ox, oy, ost, obb, planes, np.array([1]), win, 1e-13, 1e-11), "index below")
    refused(lambda: wa.solve_window(ox, oy, ost[:1].copy(), obb, planes, np.array([0]), win, 1e-13, 1e-11), "end at")
    refused(lambda: wa.solve_window(ox, oy, ost, obb, planes, np.array([0]), (0.0, 0.0, np.nan, 4.0), 1e-13, 1e-11),
            "window")
    xs, ys, labels, starts, piece_rings, sources = wa.solve_window(ox, oy, ost, obb, planes, np.array([0]), win,
                                                                   1e-13, 1e-11)
    assert sources.tolist() == [0] and wa.ring_area_of(xs, ys, 0, len(xs)) == 2.0


def test_add_coverage_refuses_mismatched_weights_and_output():
    xs, ys, _, starts = SQ
    out = np.zeros((3, 3, 2))
    refused(lambda: wa.add_coverage(xs, ys, starts, np.ones((1, 3)), out), "axis 1")
    refused(lambda: wa.add_coverage(xs, ys, starts, np.ones((2, 2)), out), "axis 0")
    refused(lambda: wa.add_coverage(xs, ys, starts, np.ones((1, 2)), np.zeros((3, 3))), "dimension")
    refused(lambda: wa.add_coverage(xs, ys, np.array([0, 2]), np.ones((1, 2)), out), "must end at")
    wa.add_coverage(xs, ys, starts, np.ones((1, 2)), out)
    assert out[..., 0].sum() == 4.0 and out[0, 0, 1] == 1.0


def test_split_convex_refuses_rows_too_short():
    xs, ys, labels, _ = SQ
    d = np.array([-1.0, 1.0, 1.0, -1.0])
    short = [np.zeros(2), np.zeros(2), np.zeros(2, np.int64), np.zeros(2), np.zeros(2), np.zeros(2, np.int64)]
    refused(lambda: wa.split_convex(xs, ys, labels, 4, d, 1e-12, 9, *short), "too short")
    refused(lambda: wa.split_convex(xs, ys, labels, 5, d, 1e-12, 9, *short), "fewer than n")
    refused(lambda: wa.vertex_sides(d, 7, 0.0), "fewer than n")


def test_components_labels_each_node_with_its_smallest():
    assert wa.components(5, np.array([3, 1]), np.array([4, 3])).tolist() == [0, 1, 2, 1, 1]
    refused(lambda: wa.components(2, np.array([0]), np.array([2])), "index below")
