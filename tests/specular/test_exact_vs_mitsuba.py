"""The exact shading against Mitsuba within Mitsuba's noise, by a stated test (the specular
groups' cross-check): 16 independent Mitsuba renders of 256 spp (4096 samples per pixel in
all), a per-pixel t-test at 0.01 with a Sidak correction, passing when 99.75 % of the pixel
channels pass (aaeval.groundtruth.agreement). The same test rejects the per-piece shading and
the exact image with its highlight 5 % too bright: it can fail."""

from pathlib import Path

import numpy as np
import pytest

from aaeval.groundtruth.agreement import agreement
from aaeval.renderers import render
from aaeval.scenes import load_scene
from aaeval.specular.exact import exact_shading

SCENES = Path(__file__).resolve().parents[2] / "configs/scenes/shaded"


@pytest.mark.slow
@pytest.mark.parametrize("name,frame", [("thin", 3), ("wide", 5)])
def test_mitsuba_agrees_with_exact_within_its_noise(name, frame):
    scene = load_scene(SCENES / f"{name}-highlight.toml").at_frame(frame)
    renders = np.array([render(scene, f"mitsuba:spp=256,seed={k}") for k in range(16)])
    exact = exact_shading(scene)
    verdict = agreement(renders, exact.image)
    assert verdict.passed, verdict
    brighter = agreement(renders, exact.image + 0.05 * exact.specular[..., None])
    assert not brighter.passed, brighter
    if name == "thin":  # one shade per piece misses the sub-pixel highlight
        assert not agreement(renders, render(scene, "catmull")).passed


def test_agreement_refuses_mismatched_shapes():
    with pytest.raises(ValueError, match="agreement"):
        agreement(np.zeros((1, 4, 4)), np.zeros((4, 4)))
