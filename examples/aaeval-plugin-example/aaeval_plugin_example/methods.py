"""Method ``blur``: the point-sampled image under a 3x3 binomial blur (a post-process baseline).

Importing this module registers the method; aaeval imports it through the entry point
``blur = "aaeval_plugin_example.methods"`` in group ``aaeval.methods``.
"""

import numpy as np

from aaeval.renderers import Option, register_method
from aaeval.renderers.sampling import point_sampled


@register_method(
    "blur",
    summary="example plugin: point sampling, then a 3x3 binomial blur mixed in by 'strength'",
    options={"strength": Option(float, 1.0, "how much of the blurred image is kept", minimum=0.0, maximum=1.0)},
    samples=lambda options: 1,
)
def render_blur(scene, strength=1.0):
    image = point_sampled(scene, 1)
    padded = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = image.shape[:2]
    kernel = np.array([1.0, 2.0, 1.0]) / 4.0
    blurred = sum(kernel[i] * kernel[j] * padded[i : i + h, j : j + w] for i in range(3) for j in range(3))
    return (1.0 - strength) * image + strength * blurred
