"""One rule for what a reference is as a truth (aaeval.metrics.agreement.truth_of): a
noise-free truth with an error bound (exact shading's quadrature) is not seeded; nothing is
divided by its bound, and agreeing with it means being within the bound plus float rounding.
The studies, the findings and the ground-truth section all read it."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from aaeval.metrics.agreement import EXACT_ROUNDING, Truth, truth_of, within_truth
from aaeval.studies.readme import BEGIN, END
from aaeval.studies.run import run_study
from aaeval.studies.study import load_study


@pytest.mark.parametrize("kind, level, expected", [
    ("stochastic", 3e-3, Truth("seeded", 3e-3)),
    ("exact", 1e-14, Truth("bounded", 1e-14)),  # exact shading: a quadrature bound is not noise
    ("exact", 0.0, Truth("exact", 0.0)),
    ("exact", math.nan, Truth("exact", 0.0)),
    ("deterministic", 0.0, Truth("unknown", math.nan)),
    ("stochastic", math.nan, Truth("unknown", math.nan)),  # seeded, but its noise was not measured
])
def test_truth_of(kind, level, expected):
    got = truth_of(kind, level)
    assert got.kind == expected.kind
    assert got.level == expected.level or (math.isnan(got.level) and math.isnan(expected.level))


def test_within_a_bound_is_the_bound_plus_rounding_never_a_multiple():
    bounded = Truth("bounded", 1e-14)
    assert within_truth(1e-14 + 0.5 * EXACT_ROUNDING, bounded)
    assert not within_truth(1e-14 + 2 * EXACT_ROUNDING, bounded)
    # a factor widens a seeded truth's noise, never a bound: 1e-11 is 1000x the bound, still off
    assert not within_truth(1e-11, bounded, factor=1e6)
    assert within_truth(0.0, Truth("exact", 0.0))
    seeded = Truth("seeded", 0.01)
    assert within_truth(0.014, seeded, factor=1.5) and not within_truth(0.016, seeded, factor=1.5)
    assert within_truth(0.0, Truth("unknown", math.nan)) is None
    assert within_truth(math.nan, seeded) is None


SHADED = """
[experiment]
name = "bounded"
reference = "catmull:shading=exact"
metrics = ["rmse"]

[[groups]]
name = "tube"
scenes = [{generator = "shininess", difficulty = [200], size = 10, frames = 2}]
methods = ["catmull:specular=none", "catmull:shading=exact"]
"""


@pytest.mark.slow
def test_a_study_against_exact_shading_divides_nothing_by_its_bound(tmp_path):
    folder = tmp_path / "bounded"
    folder.mkdir()
    (folder / "config.toml").write_text(SHADED)
    (folder / "study.toml").write_text('[study]\npaper = "J. Amanatides, test"\nseed = "x.txt"\n\n[[summaries]]\n'
                                       'kind = "errors"\ngroup = "tube"\n'
                                       'within_noise = ["catmull:shading=exact"]\n')
    (folder / "README.md").write_text(f"{BEGIN}\n{END}\n")
    run_study(load_study(folder), workers=1, cache_dir=tmp_path / "cache")
    text = (folder / "README.md").read_text()
    from aaeval.api import open_sweep

    results = open_sweep(folder / "results").results
    bound = float(results["reference_noise_rmse"].max())
    assert 0 < bound < 1e-6  # the sweep records the quadrature's bound where a seeded truth's noise goes
    assert "/ noise" not in text and "x the truth's noise" not in text
    assert "exact, no noise; error bound RMS" in text
    # the truth itself agrees within its bound; one shade per piece does not
    line = next(line for line in text.splitlines() if "within the exact truth's error bound" in line)
    assert "`catmull:shading=exact`" in line and "`catmull`" not in line.split(":", 1)[1].replace(
        "`catmull:shading=exact`", "")
    assert "**Holds**" in text


def test_charts_draw_no_noise_band_for_a_noise_free_truth():
    import pandas as pd

    from aaeval.sweeps.summaries import measured_noise

    rows = pd.DataFrame({"reference_kind": ["stochastic", "exact", "exact", "deterministic"],
                         "reference_noise_rmse": [3e-3, 2.7e-14, 0.0, 0.0]})
    noise = measured_noise(rows)
    assert noise.iloc[0] == 3e-3
    assert noise.iloc[1:].isna().all()  # the quadrature's bound is not drawn as noise
