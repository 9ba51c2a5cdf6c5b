"""The page's PNGs are drawn once (:func:`aaeval.report.figure_files.write_png`): the figure on a
canvas with room around it, its tight box measured there and cut out. That must be the image
matplotlib's own ``savefig`` draws for the same box widened to whole pixels."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402
from PIL import Image  # noqa: E402

from aaeval.report import figure_files  # noqa: E402


def _figure():
    """Text on every side, a log axis, a legend outside the axes, an image, no hatching."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(6, 3))
    x = np.linspace(1, 10, 40)
    a.plot(x, x ** 2, label="a curve with a long label")
    a.set_yscale("log")
    a.set_title("left: log axis")
    a.set_xlabel("x (px)")
    b.imshow(np.linspace(0, 1, 48).reshape(6, 8), cmap="magma")
    b.set_title("right: an image")
    fig.legend(loc="upper left", bbox_to_anchor=(0.9, 0.9))
    fig.suptitle("a figure whose tight box is not its canvas")
    return fig


def test_the_png_drawn_once_is_savefigs_image_of_the_widened_box(tmp_path):
    fig = _figure()
    box = figure_files.write_png(fig, tmp_path / "once.png")
    plt.close(fig)
    dpi = figure_files.DPI
    widened = Bbox.from_extents(math.floor(box.x0 * dpi) / dpi, math.floor(box.y0 * dpi) / dpi,
                                math.ceil(box.x1 * dpi) / dpi, math.ceil(box.y1 * dpi) / dpi)
    fig = _figure()
    fig.savefig(tmp_path / "savefig.png", format="png", dpi=dpi, bbox_inches=widened)
    plt.close(fig)
    once = np.asarray(Image.open(tmp_path / "once.png"))
    reference = np.asarray(Image.open(tmp_path / "savefig.png"))
    assert once.shape == reference.shape
    assert once.shape[1] > 1.2 * 6 * dpi  # the legend beside the axes is inside the cut
    assert (once == reference).all()
