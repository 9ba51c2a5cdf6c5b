"""Moved: the one generator registry is :mod:`aaeval.scenes.generate`.

This name stays only until its last caller (``aaeval/experiments/config.py``) imports
``from aaeval.scenes.generate import GENERATORS, generate_scene``; delete it then.
"""

from aaeval.scenes.generate import GENERATORS, Generator, generate_scene, register_generator  # noqa: F401
