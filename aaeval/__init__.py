"""aaeval: a research testbed for anti-aliasing quality."""

from aaeval import _numba_cache

_numba_cache.configure()

__version__ = "0.1.0"
