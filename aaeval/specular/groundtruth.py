"""Moved: the Phong ground truth is :mod:`aaeval.groundtruth.phong`, cached by
:mod:`aaeval.groundtruth.cache` (one cache, one default for flat and Phong truths).

This name stays only until its last callers switch to
``from aaeval.groundtruth import groundtruth_phong``; delete it then.
"""

from aaeval.groundtruth.cache import groundtruth_phong  # noqa: F401
from aaeval.groundtruth.phong import phong_scene_dict, render_mitsuba_phong  # noqa: F401
