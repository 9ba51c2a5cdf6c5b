"""Every generated scene: the builders and the one registry of generators.

- Builders (:func:`fan`, :func:`slivers`, :func:`picket_fence`, :func:`coplanar_stack` in
  :mod:`~aaeval.scenes.generate.patterns`; :func:`random_triangles`,
  :func:`random_polygons`, :func:`illustration_like` in
  :mod:`~aaeval.scenes.generate.random_scenes`) build a scene as the dictionary a TOML
  file would parse to and hand it to :func:`~aaeval.scenes.document.parse_scene`
  (:mod:`~aaeval.scenes.generate.build`), so what they return has passed the same
  validation as a file.
- Generators (:data:`GENERATORS`, :func:`register_generator`, :func:`generate_scene`, in
  :mod:`~aaeval.scenes.generate.registry`): scenes built from one *difficulty* value,
  which sweeps raise to find where each method starts to fail; the flat ones are in
  :mod:`~aaeval.scenes.generate.flat`, the shaded cylinder's in
  :mod:`~aaeval.scenes.generate.cylinders`, the parameters they share in
  :mod:`~aaeval.scenes.generate.params`. Importing this package registers them all.
"""

from aaeval.scenes.generate.patterns import coplanar_stack, fan, picket_fence, slivers
from aaeval.scenes.generate.random_scenes import illustration_like, random_polygons, random_triangles
from aaeval.scenes.generate.registry import (
    GENERATORS,
    MAX_PIXEL_FRAMES,
    MAX_POLYGONS,
    Generator,
    GeneratorError,
    generate_scene,
    register_generator,
)

# the generator modules register on import, in this order (the order they are listed in)
from aaeval.scenes.generate import flat  # noqa: E402,F401
from aaeval.scenes.generate import cylinders  # noqa: E402,F401

__all__ = [
    "GENERATORS",
    "Generator",
    "GeneratorError",
    "coplanar_stack",
    "MAX_POLYGONS",
    "MAX_PIXEL_FRAMES",
    "register_generator",
    "generate_scene",
    "fan",
    "illustration_like",
    "picket_fence",
    "random_polygons",
    "random_triangles",
    "slivers",
]
