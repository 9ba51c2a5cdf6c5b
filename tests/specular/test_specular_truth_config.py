"""Every group of the shipped experiments that measures a highlight metric is judged against
the noise-free exact shading and keeps Mitsuba at 4096 spp or more as its cross-check row."""

from pathlib import Path

import pytest

from aaeval.sweeps import load_experiment

EXPERIMENTS = Path(__file__).resolve().parents[2] / "configs/sweeps"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["default", "specular"])
def test_highlight_groups_are_judged_against_the_exact_truth(name):
    groups = [g for g in load_experiment(EXPERIMENTS / f"{name}.toml").groups
              if any(m.startswith("highlight") for m in (*g.metrics, *g.temporal))]
    assert groups
    for g in groups:
        assert str(g.reference) == "catmull:shading=exact", (g.name, str(g.reference))
        assert g.reference.method.exact
        checks = [s for s in g.specs if s.method.name == "mitsuba" and int(s.options["spp"]) >= 4096]
        assert checks, f"{g.name}: no Mitsuba cross-check row"
