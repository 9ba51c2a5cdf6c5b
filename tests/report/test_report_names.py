"""Names in the report are text, never markup, mathtext or paths."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.helpers.sweep_util import SMALL, write_config

TRICKY = ["fence a", "fence-a", "fence_a", "x $\\frac{$ y", "cost $5 to $10", "../../etc", "", ".", "a/b",
          "A", "a", "é" * 300, "<b>bold</b>"]


def test_figure_stems_are_unique_safe_file_names_whatever_the_names():
    from aaeval.report.names import figure_stem

    stems = [figure_stem(n) for n in TRICKY]
    assert len(set(stems)) == len(set(s.lower() for s in stems)) == len(TRICKY)  # also on case-blind disks
    for stem in stems:
        assert stem and len(stem.encode()) <= 100 and Path(stem).name == stem and not stem.startswith(".")
        assert all(ch.isascii() and (ch.isalnum() or ch in "-_") for ch in stem)
    assert figure_stem("fence a") == figure_stem("fence a")  # stable between runs


def test_user_text_in_figures_is_never_mathtext(tmp_path):
    import matplotlib.pyplot as plt

    import aaeval.report.figures  # noqa: F401  (sets the report's matplotlib defaults)

    fig, ax = plt.subplots()
    crash = ax.set_title("x $\\frac{$ y")  # was: ParseSyntaxException at draw time
    price = ax.set_xlabel("cost $5 to $10")  # was: drawn as an italic "5to10"
    assert not crash.get_parse_math() and not price.get_parse_math()
    fig.savefig(tmp_path / "t.png")
    plt.close(fig)


@pytest.mark.slow
def test_report_of_groups_whose_names_slug_alike_keeps_each_groups_figures(tmp_path):
    from aaeval.sweeps import load_experiment, run_sweep
    from aaeval.report import write_report

    text = SMALL.replace('name = "edges"', 'name = "fence a"').replace('name = "stability"', 'name = "fence-a"')
    text = text.replace('description = "test sweep"', 'description = "x $\\\\frac{$ y"')
    text += SMALL[SMALL.index("[[groups]]\nname = \"stability\""):].replace('"stability"', '"x $\\\\frac{$ y"')
    exp = load_experiment(write_config(tmp_path, text))
    out = tmp_path / "out"
    run_sweep(exp, out, workers=1, quiet=True, cache_dir=tmp_path / "cache")
    index = write_report(out, formats=("png",))  # the collision is in the figures' stems, the same for every format
    page = index.read_text()
    figs = sorted(p.name for p in (out / "figures").glob("*.png"))
    stems = {}
    for group in ("fence a", "fence-a", "x $\\frac{$ y"):
        section = page.split(f">{group}</h2>")[1].split("<h2")[0]
        srcs = {s.split("'")[0] for s in section.split("src='")[1:]}
        assert srcs, group
        stems[group] = srcs
    from aaeval.report.names import figure_stem

    assert not (stems["fence a"] & stems["fence-a"])  # no group shows another's charts
    assert not (stems["fence-a"] & stems["x $\\frac{$ y"])
    for group, srcs in stems.items():
        pngs = [s for s in srcs if s.endswith(".png")]
        assert pngs and all(figure_stem(group) in s and (out / s).is_file() for s in pngs), (group, srcs)
    assert figs
