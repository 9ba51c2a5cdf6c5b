"""The compiled kernels: C++17 from ``src/``, bound with nanobind, built at install.

One module per kernel family, each imported by the Python layer that owns it:

- :mod:`aaeval.native.catmull`: Catmull 1978's scan stages, pixel integrator and sinks
  (colour, fragments, filter moments); used by :mod:`aaeval.catmull`.
- :mod:`aaeval.native.weiler_atherton`: the Weiler-Atherton clipper, hidden-surface solver,
  near-tie regions and box filter; used by :mod:`aaeval.weiler_atherton`.
- :mod:`aaeval.native.samplers`: point sampling (point, supersample, jitter, MSAA), the
  A-buffer, the depth tie rule and the simplicity sweep; used by :mod:`aaeval.renderers`
  and :mod:`aaeval.scenes`.
- :mod:`aaeval.native.shading`: the Phong shade integrated exactly over Catmull's visible
  pieces; used by :mod:`aaeval.specular`.

Each family's ``module.cpp`` holds its bindings only; the kernels are the family's other
files. The bindings only the tests call (a kernel's stages and inner pieces) are modules of
their own: ``catmull_testing``, ``weiler_atherton_testing``, ``samplers_testing``.

Every binding checks its arrays once (dtype, shape, finiteness, ranges) and raises a
one-line ``ValueError``; the kernels release the GIL.
"""
