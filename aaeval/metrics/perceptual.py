"""Perceptual difference: NVIDIA FLIP (Andersson et al. 2020) through ``flip-evaluator``."""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_image_pair, check_positive
from aaeval.metrics._pairs import once_per_pair

__all__ = ["flip", "flip_map"]


def flip(image_true, image_test, *, ppd: float | None = None) -> float:
    """Mean LDR-FLIP error of a test image against a reference.

    The images are linear sRGB; they are clipped to [0, 1] and handed to
    ``flip_evaluator.evaluate(..., "LDR", inputsRGB=False)``, which encodes them with the
    sRGB transfer function itself before LDR-FLIP (checked: the same error as giving it
    sRGB-encoded images with ``inputsRGB=True``).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear sRGB), the same shape.
    ppd : float, optional
        Pixels per degree of visual angle. By default FLIP's own (about 67: a 0.7 m wide
        3840-pixel monitor seen from 0.7 m).

    Returns
    -------
    flip : float
        Mean of the per-pixel FLIP error, in [0, 1]; 0 for identical images.
    """
    _, mean = _evaluated(image_true, image_test, ppd)
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
    fmap, _ = _evaluated(image_true, image_test, ppd)
    return np.asarray(fmap, dtype=np.float32).reshape(np.shape(image_true)[:2])


@once_per_pair
def _evaluated(image_true, image_test, ppd):
    """(map, mean) of the pair, checked first; inside
    :func:`aaeval.metrics._pairs.maps_once_per_pair` a pair seen before gives what it gave
    then: a sweep cell takes the mean as the ``flip`` metric and the map for the viewer."""
    checked_true, checked_test = check_image_pair(image_true, image_test)
    if ppd is not None:
        check_positive("ppd", ppd)
    return _evaluate(checked_true, checked_test, ppd)


def _evaluate(image_true, image_test, ppd):
    import flip_evaluator

    with _one_thread():
        fmap, value, _ = flip_evaluator.evaluate(
            np.clip(image_true, 0.0, 1.0),
            np.clip(image_test, 0.0, 1.0),
            "LDR",
            inputsRGB=False,
            applyMagma=False,
            computeMeanError=True,
            parameters={} if ppd is None else {"ppd": float(ppd)},
        )
    return fmap, value


_OPENMP = None


def _one_thread():
    """FLIP's OpenMP runtime (the libgomp flip-evaluator ships) limited to one thread for a
    call. Each pixel's error is computed alone, so the map is the same whatever the number of
    threads; but a team of threads costs more than it gives on the small images of a sweep,
    where each core already runs its own worker: 32 calls on 24 x 24 pixels took 2.1 s with
    two threads beside another busy process, 53 ms with one (benchmarks/results/bench_sweep.md)."""
    global _OPENMP
    if _OPENMP is None:
        from threadpoolctl import ThreadpoolController

        _OPENMP = ThreadpoolController().select(user_api="openmp")
    return _OPENMP.limit(limits=1)
