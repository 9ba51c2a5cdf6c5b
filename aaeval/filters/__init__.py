"""Pixel reconstruction filters beyond the box, integrated exactly over visible pieces.

- :mod:`.registry`: the one registry of filters (Mitsuba 3's definitions);
- :mod:`.integrate`: the native stages (``aaeval.native.catmull``, ``src/catmull/moments.hpp``):
  a visible piece's integrals against the filter per knot cell (Green's theorem), cells
  combined into pixels;
- :mod:`aaeval.catmull.filtered`: the Catmull kernel's visible pieces on the knot grid,
  through its moment sink, straight to pixel sums;
- :mod:`.evaluate`: point evaluation of a profile (native), for samplers that splat;
- :mod:`.exact`: the exactly filtered image of a scene.
"""

from aaeval.filters.registry import (
    DEFAULT_FILTER,
    FILTERS,
    PixelFilter,
    axis_weights,
    filter_names,
    get_filter,
)

__all__ = ["DEFAULT_FILTER", "FILTERS", "PixelFilter", "axis_weights", "filter_names", "get_filter"]
