"""Perceptual difference: NVIDIA FLIP (Andersson et al. 2020) through ``flip-evaluator``."""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np

from aaeval.metrics._checks import check_image_pair, check_positive

__all__ = ["flip", "flip_map", "one_flip_per_pair"]

# Inside one_flip_per_pair(): what FLIP gave for the pairs of arrays seen there, by identity.
_SEEN: list | None = None


@contextmanager
def one_flip_per_pair():
    """Within this block FLIP is evaluated once per pair of arrays (the same objects, not
    changed in between): a sweep cell takes its mean as the ``flip`` metric and its map for
    the viewer, and one evaluation gives both (about 30 ms of a 512 x 512 cell)."""
    global _SEEN
    outer, _SEEN = _SEEN, []
    try:
        yield
    finally:
        _SEEN = outer


def flip(image_true, image_test, *, ppd: float | None = None) -> float:
    """Mean LDR-FLIP error of a test image against a reference.

    The images are linear sRGB; they are clipped to [0, 1] and handed to
    ``flip_evaluator.evaluate(..., "LDR", inputsRGB=False)``, which encodes them with the
    sRGB transfer function itself before LDR-FLIP (checked: the same error as giving it
    sRGB-encoded images with ``inputsRGB=True``).

    Parameters
    ----------
    image_true : ndarray, shape (H, W, 3)
        Reference image (linear sRGB).
    image_test : ndarray, shape (H, W, 3)
        Test image, same shape.
    ppd : float, optional
        Pixels per degree of visual angle. By default FLIP's own (about 67: a 0.7 m wide
        3840-pixel monitor seen from 0.7 m).

    Returns
    -------
    flip : float
        Mean of the per-pixel FLIP error, in [0, 1]; 0 for identical images.
    """
    _, mean = _evaluated(image_true, image_test, ppd, mean=True)
    return float(mean)


def flip_map(image_true, image_test, *, ppd: float | None = None) -> np.ndarray:
    """Per-pixel LDR-FLIP error map of a test image against a reference: the map whose mean
    :func:`flip` is (the same clipping, encoding and viewing distance).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        Reference and test image (linear sRGB).
    ppd : float, optional
        Pixels per degree of visual angle (FLIP's own by default).

    Returns
    -------
    ndarray, shape (H, W), float32
        The FLIP error of every pixel, in [0, 1].
    """
    fmap, _ = _evaluated(image_true, image_test, ppd, mean=False)
    return np.asarray(fmap, dtype=np.float32).reshape(np.shape(image_true)[:2])


def _evaluated(image_true, image_test, ppd, *, mean: bool):
    """(map, mean) of the pair, checked first; inside :func:`one_flip_per_pair` a pair seen
    before gives what it gave then (its mean always computed there)."""
    if _SEEN is not None:
        for a, b, p, found in _SEEN:
            if a is image_true and b is image_test and p == ppd:
                return found
    checked_true, checked_test = check_image_pair(image_true, image_test)
    if ppd is not None:
        check_positive("ppd", ppd)
    found = _evaluate(checked_true, checked_test, ppd, mean=mean or _SEEN is not None)
    if _SEEN is not None:
        _SEEN.append((image_true, image_test, ppd, found))
    return found


def _evaluate(image_true, image_test, ppd, *, mean: bool):
    import flip_evaluator

    fmap, value, _ = flip_evaluator.evaluate(
        np.clip(image_true, 0.0, 1.0),
        np.clip(image_test, 0.0, 1.0),
        "LDR",
        inputsRGB=False,
        applyMagma=False,
        computeMeanError=mean,
        parameters={} if ppd is None else {"ppd": float(ppd)},
    )
    return fmap, value
