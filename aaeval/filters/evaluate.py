"""Point evaluation of a registered filter's profile, for samplers that splat.

The one evaluation of ``k(t)`` is native (``src/samplers``, bound as
``aaeval.native.samplers.profile_array``, the samplers' own splat weight): box ``|t| <= 1/2``
(Mitsuba's box is closed), the Gaussian, or the polynomial piece of ``t`` by Horner in the
piece's local variable. :meth:`PixelFilter.profile` and the sampling baselines both call
it; a filter reaches it as the tuple
:func:`aaeval.filters.registry.profile_args` returns.
"""

from __future__ import annotations

import numpy as np

from aaeval.native.samplers import profile_array as _profile_array

__all__ = ["profile_at", "profile_array"]


def profile_array(kind, radius, pieces, alpha, bias, t) -> np.ndarray:
    """``k(t)`` at every entry of a flat float64 array ``t`` (native)."""
    return _profile_array(int(kind), float(radius), np.ascontiguousarray(pieces, dtype=np.float64), float(alpha),
                          float(bias), np.ascontiguousarray(t, dtype=np.float64))


def profile_at(kind, radius, pieces, alpha, bias, t) -> float:
    """``k(t)`` at one point."""
    return float(profile_array(kind, radius, pieces, alpha, bias, np.array([t], dtype=np.float64))[0])
