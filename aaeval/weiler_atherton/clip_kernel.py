"""The Weiler-Atherton clipper's kernels under their old module name: the native ones
(``aaeval._weiler_atherton``, C++ in ``src/weiler_atherton/``) re-exported.

The numba clipper that lived here was ported to C++ (issue 20); :mod:`.clipper` is the
API. This name stays only because the ground-truth cache key
(``aaeval/groundtruth/cache.py``, ``CODE_FILES``) still reads this file.
"""

from aaeval._weiler_atherton import clip_arrays, first_crossing, ring_area_of, winding

__all__ = ["clip_arrays", "ring_area_of", "winding", "first_crossing"]
