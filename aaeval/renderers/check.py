"""The image check: the rules every method's result follows, and the one error of a method
that broke them or raised (:class:`MethodFailure`)."""

from __future__ import annotations

import math

import numpy as np

from aaeval.renderers.registry import MethodError

__all__ = ["MAX_PIXEL_MAGNITUDE", "MethodFailure", "check_image"]


class MethodFailure(MethodError):
    """A method that raised, or returned something that is not an image of its scene: one
    line naming the method and the rule (an input error of the plugin, exit 2 from the CLI;
    a failed row in compare and sweeps)."""


# Far above any radiance a scene here holds, far below where a squared error or an
# image's sum overflows float64 (a -1e300 image would make every error metric infinite).
MAX_PIXEL_MAGNITUDE = 1e100


def check_image(name: str, image, shape: tuple[int, int, int]) -> np.ndarray:
    """The rules every method's result follows: an ndarray of real floats, the scene's
    ``(H, W, 3)``, every value finite and within
    :data:`MAX_PIXEL_MAGNITUDE`. Returns ``image``; :class:`MethodFailure` otherwise."""
    where = f"method {name!r}"
    if not isinstance(image, np.ndarray):
        raise MethodFailure(f"{where} returned {type(image).__name__}, expected a numpy array of shape {shape}")
    if image.dtype.kind != "f":
        raise MethodFailure(f"{where} returned dtype {image.dtype}, expected real floats (float64 linear RGB)")
    if image.shape != shape:
        raise MethodFailure(f"{where} returned shape {image.shape}, expected {shape}")
    if not image.size:
        return image
    # the extremes alone (a NaN among the values is the extremes' NaN): no temporary image
    lo, hi = float(image.min()), float(image.max())
    if not (math.isfinite(lo) and math.isfinite(hi)):
        bad = int(np.count_nonzero(~np.isfinite(image)))
        raise MethodFailure(f"{where} returned {bad} value(s) that are NaN or infinite; every value must be finite")
    if max(-lo, hi) > MAX_PIXEL_MAGNITUDE:
        raise MethodFailure(f"{where} returned a value of magnitude {max(-lo, hi):.3g}; every value "
                            f"must be within +-{MAX_PIXEL_MAGNITUDE:g} (so that errors and sums stay finite)")
    return image

