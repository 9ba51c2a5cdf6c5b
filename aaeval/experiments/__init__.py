"""Experiments built on the renderers and metrics: comparisons, sweeps."""
