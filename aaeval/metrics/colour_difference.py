"""Colour difference CIEDE2000 between a test image and a reference (colour-science).

Conversion path, per pixel: the renderers' linear RGB is linear sRGB (ITU-R BT.709
primaries, D65 white), so it goes to CIE XYZ through colour-science's ``"sRGB"``
colourspace matrix (``colour.RGB_to_XYZ(..., "sRGB")`` with ``apply_cctf_decoding=False``:
encoding to sRGB and decoding again is the identity, so no transfer function is applied),
then to CIE L*a*b* with the D65 white point of the CIE 1931 2 degree observer
(``colour.XYZ_to_Lab``), then ``colour.delta_E(..., method="CIE 2000")`` (Sharma, Wu &
Dalal 2005). Values are not clipped: out-of-gamut colours are converted as they are.
"""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_image_pair
from aaeval.metrics._pairs import once_per_pair

__all__ = ["linear_rgb_to_lab", "ciede2000_map", "ciede2000_maps", "ciede2000_mean", "ciede2000_p95"]


def linear_rgb_to_lab(image) -> np.ndarray:
    """Linear sRGB (D65) to CIE L*a*b* (D65, 2 degree observer); L* of white is 100."""
    import colour

    srgb = colour.RGB_COLOURSPACES["sRGB"]
    xyz = colour.RGB_to_XYZ(np.asarray(image, dtype=np.float64), srgb, apply_cctf_decoding=False)
    return colour.XYZ_to_Lab(xyz, srgb.whitepoint)


@once_per_pair
def ciede2000_map(image_true, image_test) -> np.ndarray:
    """Per-pixel CIEDE2000 colour difference, shape (H, W); computed once per pair inside
    :func:`aaeval.metrics._pairs.maps_once_per_pair` (the mean and the 95th percentile of a
    sweep cell read one map).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear sRGB), the same shape.

    Returns
    -------
    delta_e : ndarray, shape (H, W)
        Delta E 2000 of every pixel (conversion path in the module docstring).
    """
    image_true, image_test = check_image_pair(image_true, image_test)
    import colour

    return colour.delta_E(linear_rgb_to_lab(image_true), linear_rgb_to_lab(image_test), method="CIE 2000")


def ciede2000_maps(pairs) -> None:
    """The CIEDE2000 maps of many ``(image_true, image_test)`` pairs, computed together (one
    conversion and one colour difference per image size) and kept for :func:`ciede2000_map`
    inside :func:`aaeval.metrics._pairs.maps_once_per_pair`. Every step is per pixel, so each
    map is the one a call per pair gives, bit for bit. A pair that fails the checks is left
    to its own call (which raises there)."""
    import colour

    by_shape: dict[tuple, list] = {}
    for image_true, image_test in pairs:
        try:
            checked = check_image_pair(image_true, image_test)
        except ValueError:
            continue
        by_shape.setdefault(checked[0].shape, []).append(((image_true, image_test), checked))
    for group in by_shape.values():
        if len(group) < 2:
            continue  # alone, its own call costs the same
        maps = colour.delta_E(linear_rgb_to_lab(np.stack([c[0] for _, c in group])),
                              linear_rgb_to_lab(np.stack([c[1] for _, c in group])), method="CIE 2000")
        for ((image_true, image_test), _), delta_e in zip(group, maps):
            ciede2000_map.remember(image_true, image_test, delta_e)


def ciede2000_mean(image_true, image_test) -> float:
    """Mean over pixels of the CIEDE2000 colour difference (see :func:`ciede2000_map`).

    Returns
    -------
    delta_e : float
        0 for identical images; about 1 is a just-noticeable difference.
    """
    return float(np.mean(ciede2000_map(image_true, image_test)))


def ciede2000_p95(image_true, image_test) -> float:
    """95th percentile over pixels of the CIEDE2000 colour difference (see :func:`ciede2000_map`).

    The percentile is numpy's default (linear interpolation between order statistics).
    It reports the error of the worst pixels, which a mean over a mostly flat image hides.
    """
    return float(np.percentile(ciede2000_map(image_true, image_test), 95.0))
