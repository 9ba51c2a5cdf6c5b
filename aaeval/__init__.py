"""aaeval: a research testbed for anti-aliasing quality."""

__version__ = "0.1.0"
