"""Controls of the per-cross-section highlight measure at any direction and on a curve.

The truth is a thin highlight (0.4 px wide, unit energy per unit length) drifting by
sub-pixel steps (0.137, 0.061) px a frame, box-filtered exactly: each pixel's value is the
area of the pixel square inside the highlight, computed by GEOS (shapely), independently of
the measure's own arithmetic. Straight highlights cross the whole image at 0, 19, 45 and 90
degrees (one also spins 0.25 degrees a frame, as a cylinder's highlight does); the curved one
is an arc of a circle of radius 40 px whose centre lies outside the image.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

import shapely

from aaeval.metrics import registry  # noqa: E402
from aaeval.metrics.specular import highlight_mask  # noqa: E402

SIZE, FRAMES, WIDTH = 40, 12, 0.4
STEP = np.array([0.137, 0.061])
POP = 0.2
# Tolerances, each beside the control it bounds:
EXACT = 1e-12  # truth and steady bias: the steady gain per cross-section removes a bias exactly
POP_REL = 1e-4  # popping: measured within 3e-7 of 0.2 (the truth's cross-sections move a little)
BLUR = 1e-3  # steady 1 px blur: measured 1e-16 (0, 90 deg) to 1.4e-4 (45 deg); row sums read 1.6e-2 to 0.23 at 0-45 deg


def _pixels():
    rows, cols = np.mgrid[0:SIZE, 0:SIZE]
    return shapely.box(cols.ravel(), rows.ravel(), cols.ravel() + 1, rows.ravel() + 1)


def _box_filtered(shapes, width=WIDTH):
    pixels = _pixels()
    frames = np.zeros((len(shapes), SIZE * SIZE))
    for frame, shape in zip(frames, shapes):
        shapely.prepare(shape)
        touched = shapely.intersects(shape, pixels)
        frame[touched] = shapely.area(shapely.intersection(pixels[touched], shape)) / width
    return frames.reshape(len(shapes), SIZE, SIZE)


def _line(degrees, spin=0.0, centre=(19.3, 23.1), width=WIDTH):
    shapes = []
    for t in range(FRAMES):
        angle = np.radians(degrees + spin * t)
        along = 100.0 * np.array([np.cos(angle), np.sin(angle)])
        across = 0.5 * width * np.array([-np.sin(angle), np.cos(angle)])
        middle = np.asarray(centre) + t * STEP
        shapes.append(shapely.Polygon([middle - along - across, middle + along - across,
                                       middle + along + across, middle - along + across]))
    return shapes


def _arc(radius=40.0, centre=(-12.7, 24.2)):
    # the part of the ring that crosses the image, its sides 4e-6 px from the true circles
    angle = np.radians(np.linspace(-50.0, 50.0, 4001))
    unit = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    shapes = []
    for t in range(FRAMES):
        middle = np.asarray(centre) + t * STEP
        shapes.append(shapely.Polygon(np.concatenate([middle + (radius + WIDTH / 2) * unit,
                                                      middle + (radius - WIDTH / 2) * unit[::-1]])))
    return shapes


SHAPES = {
    "0 deg": lambda: _line(0.0),
    "19 deg": lambda: _line(19.0),
    "19 deg spinning": lambda: _line(19.0, spin=0.25),
    "45 deg": lambda: _line(45.0),
    "90 deg": lambda: _line(90.0),
    "arc": _arc,
}


@pytest.fixture(scope="module", params=list(SHAPES))
def highlight(request):
    truth = _box_filtered(SHAPES[request.param]())
    return request.param, truth, np.stack([highlight_mask(f) for f in truth])


def _score(truth, test, mask):
    rgb = lambda frames: np.repeat(frames[..., None], 3, axis=-1)  # noqa: E731
    return registry.compute_temporal_metric("highlight_profile_flicker", rgb(truth), rgb(test), mask=mask)


def _steady_blur(truth):
    return np.stack([ndimage.gaussian_filter(f, sigma=1.0, mode="nearest") for f in truth])


def test_steady_truth_and_bias_score_zero(highlight):
    _, truth, mask = highlight
    assert _score(truth, truth, mask) == pytest.approx(0.0, abs=EXACT)
    assert _score(truth, 0.5 * truth, mask) == pytest.approx(0.0, abs=EXACT)
    # the bias is read by the bias measure, not lost
    assert registry.compute_temporal_metric("highlight_bias", truth, 0.5 * truth, mask=mask) == pytest.approx(-0.5)


def test_popping_scores_the_popping(highlight):
    _, truth, mask = highlight
    alternate = np.where(np.arange(FRAMES) % 2 == 0, 1.0, -1.0)[:, None, None]
    assert _score(truth, truth * (1.0 + POP * alternate), mask) == pytest.approx(POP, rel=POP_REL)


def test_steady_blur_is_steady(highlight):
    _, truth, mask = highlight
    assert _score(truth, _steady_blur(truth), mask) < BLUR


@pytest.mark.parametrize("degrees", [0.0, 4.6, 19.0, 45.0, 85.4, 90.0])
def test_a_steady_wider_highlight_is_steady(degrees):
    # The same highlight 2 px wide (the same energy per length, box-filtered exactly) moving
    # with the truth: steady, though each pixel's share of its energy differs from the
    # truth's as both drift across a row or column. Measured at most 2.9e-5 (45 deg); cut
    # exactly perpendicular to the highlight instead, 4e-3 at 4.6 and 85.4 deg.
    truth = _box_filtered(_line(degrees))
    wide = _box_filtered(_line(degrees, width=2.0), width=2.0)
    mask = np.stack([highlight_mask(f) for f in truth])
    assert _score(truth, wide, mask) < BLUR


def _row_sums_flicker(truth, test, mask):
    """The same flicker with each image row as a cross-section (what a measure that always
    sums rows reads): the rows' energies, their steady gains removed."""
    region = ndimage.binary_dilation(mask.any(axis=0), structure=np.ones((1, 9), bool))
    p, q = (truth * region).sum(axis=2), (test * region).sum(axis=2)
    power = (p * p).sum(axis=0)
    lit = power > 0
    gain = (p * q).sum(axis=0)[lit] / power[lit]
    return np.sqrt(((q[:, lit] - gain * p[:, lit]) ** 2).sum() / power.sum())


@pytest.mark.parametrize("shape", ["0 deg", "19 deg", "19 deg spinning"])
def test_row_sums_fail_the_steady_blur_control_away_from_vertical(shape):
    # The controls above have teeth: summed along rows, a steady blur of a highlight that
    # does not run down the image reads as flicker well above BLUR.
    truth = _box_filtered(SHAPES[shape]())
    mask = np.stack([highlight_mask(f) for f in truth])
    assert _row_sums_flicker(truth, _steady_blur(truth), mask) > 5 * BLUR
    vertical = _box_filtered(SHAPES["90 deg"]())  # and on a vertical one rows are cross-sections
    vmask = np.stack([highlight_mask(f) for f in vertical])
    assert _row_sums_flicker(vertical, _steady_blur(vertical), vmask) < BLUR


def test_a_given_direction_is_taken_straight():
    truth = _box_filtered(SHAPES["19 deg"]())
    mask = np.stack([highlight_mask(f) for f in truth])
    rgb = lambda frames: np.repeat(frames[..., None], 3, axis=-1)  # noqa: E731

    def blur_at(direction):
        return registry.compute_temporal_metric("highlight_profile_flicker", rgb(truth), rgb(_steady_blur(truth)),
                                                mask=mask, direction=direction)

    across = blur_at(19.0)
    assert across < BLUR
    assert blur_at(19.0 + 90.0) > 10 * across  # cut along the highlight instead of across it
    with pytest.raises(ValueError, match="direction"):
        blur_at(float("nan"))
