"""PNG round trip against sRGB written here: IEC 61966-2-1's piecewise transfer function,
and colour-science's implementation of it as a second, independent reference."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from aaeval.imageio import load_image, save_image


def srgb_encode(linear):
    """IEC 61966-2-1: V = 12.92 L for L <= 0.0031308, else 1.055 L^(1/2.4) - 0.055."""
    linear = np.asarray(linear, dtype=np.float64)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055)


def srgb_decode(encoded):
    """IEC 61966-2-1 inverse: L = V / 12.92 for V <= 0.04045, else ((V + 0.055) / 1.055)^2.4."""
    encoded = np.asarray(encoded, dtype=np.float64)
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def png_bytes(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int64)


def test_every_8_bit_code_survives_the_round_trip(tmp_path):
    codes = np.arange(256)
    linear = srgb_decode(codes / 255.0)
    image = np.stack([linear, linear[::-1], np.roll(linear, 85)], axis=1).reshape(16, 16, 3)
    path = save_image(tmp_path / "codes.png", image)
    np.testing.assert_array_equal(png_bytes(path), np.stack([codes, codes[::-1], np.roll(codes, 85)], 1).reshape(16, 16, 3))
    np.testing.assert_allclose(load_image(path), image, rtol=0, atol=1e-12)


def test_png_codes_are_the_nearest_to_the_standard_encoding(tmp_path):
    rng = np.random.default_rng(7)
    # dense near black (the linear segment and the knee at 0.0031308) and over [0, 1]
    linear = np.concatenate([rng.uniform(0, 0.01, 3 * 4096), rng.uniform(0, 1, 3 * 4096)]).reshape(64, 128, 3)
    path = save_image(tmp_path / "random.png", linear)
    exact = srgb_encode(linear) * 255.0
    codes = png_bytes(path)
    assert np.abs(codes - exact).max() <= 0.5 + 1e-9  # the nearest code, half a step at most
    np.testing.assert_array_equal(codes, np.round(exact).astype(np.int64))


def test_png_encoding_agrees_with_colour_science(tmp_path):
    import colour
    linear = np.linspace(0.0, 1.0, 3 * 40 * 40).reshape(40, 40, 3)
    path = save_image(tmp_path / "ramp.png", linear)
    reference = np.round(colour.cctf_encoding(linear, function="sRGB") * 255.0)
    assert np.abs(png_bytes(path) - reference).max() <= 1  # rounding at exact ties may differ
    assert (png_bytes(path) == reference).mean() > 0.999


def test_png_clips_out_of_range_light(tmp_path):
    image = np.array([[[-0.5, 0.0, 1.0], [1.5, 1e9, 0.5]]])
    codes = png_bytes(save_image(tmp_path / "clip.png", image))
    np.testing.assert_array_equal(codes, [[[0, 0, 255], [255, 255, round(srgb_encode(0.5) * 255)]]])
