"""One style per method: every figure of the default report, drawn from a synthetic results
table with every method and option of configs/sweeps/default.toml, shows each spec in
one colour and marker, each method in one marker and colour family, legends sorted by
option value, and tick labels that do not collide."""

from __future__ import annotations

import colorsys
import itertools
import json
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib import pyplot as plt
from matplotlib.colors import to_rgb
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from aaeval.sweeps.table import short_label
from aaeval.renderers import format_spec, resolve
from aaeval.report import figures
from aaeval.sweeps.aggregate import failed_cells, spec_summary
from aaeval.report.style import METHOD_STYLES, Styles, method_style

# one worker draws the module's figures once (pyproject's --dist loadgroup; split across two
# workers each would draw them), and keeps them for the session: a module-scoped fixture is
# torn down and drawn again when that worker runs another module's tests between these
# slow: every chart kind drawn for every group (about 10 s)
pytestmark = [pytest.mark.xdist_group("report_style"), pytest.mark.slow]

DEFAULT = Path(__file__).parents[2] / "configs" / "sweeps" / "default.toml"
# the one figure the style fixture writes to files (every format); the others are drawn only
SAVED = "validation"


def _default_specs() -> dict[str, list[tuple[str, dict]]]:
    """Per group of default.toml: (method, options) of every spec it expands to."""
    doc = tomllib.loads(DEFAULT.read_text())
    out = {}
    for group in doc["groups"]:
        specs = []
        for spec in group["methods"]:
            method, _ = resolve(spec)
            table = group.get("options", {}).get(method.name, {})
            keys = sorted(table)
            for combo in itertools.product(*(table[k] for k in keys)):
                _, opts = resolve(spec, **dict(zip(keys, combo)))
                specs.append((method.name, opts))
        out[group["name"]] = specs
    return out


def _synthetic_results() -> pd.DataFrame:
    rng = np.random.default_rng(7)
    rows = []
    for group, specs in _default_specs().items():
        for (method, opts), difficulty, frame in itertools.product(specs, (1.0, 2.0, 4.0), range(3)):
            spec = format_spec(method, opts)
            exact = resolve(spec)[0].exact
            t = float(rng.uniform(1e-3, 1.0))
            err = 1e-3 * rng.uniform(0.9, 1.1) if exact else float(rng.uniform(2e-3, 0.2))
            rows.append({"group": group, "scene": f"s@{difficulty:g}", "method": method, "spec": spec,
                         "options": json.dumps(opts, sort_keys=True), "frame": frame,
                         "label": short_label(spec, {"k", "spp", "specular"}),
                         "difficulty": difficulty, "difficulty_label": "difficulty", "rmse": err,
                         "render_s": t, "render_s_min": t * 0.9, "render_s_max": t * 1.2, "repeats": 5,
                         "width": 256, "height": 256, "intensity_sum": 100.0 + rng.normal(),
                         "reference_intensity_sum": 100.0, "reference_noise_rmse": 1e-3, "error": None,
                         "key": f"{group}-{spec}-{difficulty}-{frame}", "reference": "mitsuba:spp=4096"})
    return pd.DataFrame(rows)


def _use_registered_metrics(folder: Path) -> None:
    """The metric descriptions the figures label with, stored and read as a sweep's are."""
    from aaeval.metrics import METRICS as REGISTERED
    from aaeval.report.sweep_data import use_metrics

    (folder / "metrics.json").write_text(json.dumps({n: m.info().to_dict() for n, m in REGISTERED.items()}))
    use_metrics(folder)


def _styles(specs) -> Styles:
    """The styles of (method, options text) pairs, as a report gets them: through the specs
    the sweep stores (``specs.json``)."""
    from aaeval.sweeps.report_files import specs_of

    method, options = zip(*specs)
    return Styles.from_sweep(specs_of(pd.DataFrame({"method": method, "options": options})))


@pytest.fixture(scope="session")
def drawn(tmp_path_factory):
    """Every chart kind of the report for every group, as (name, figure) pairs."""
    out = tmp_path_factory.mktemp("style")
    _use_registered_metrics(out)
    results = _synthetic_results()
    styles = _styles(zip(results["method"], results["options"]))
    made = []
    save = figures.save_figure

    def keep(fig, path):
        figures._plain_log_axes(fig)  # as save_figure does before writing
        fig.draw_without_rendering()  # lay out at the saved size, for the collision check (no pixels)
        made.append((Path(path).stem, fig, _tick_collisions(fig)))
        if Path(path).stem == SAVED:  # every chart is drawn; one is written in every format (the
            with figures.drawing(figures.FORMATS):  # writing costs 80% of the time and is the same code for all)
                return save(fig, path)
        plt.close(fig)
        return Path(path).with_suffix(".png")

    figures.save_figure = keep
    try:
        failed = failed_cells(results, "rmse", 0.05)
        for group, rows in results.groupby("group", sort=False):
            summary = spec_summary(rows, ["rmse"], "rmse", failed)
            figures.speed_accuracy(summary, out / f"{group}_speed", metric="rmse", title=group, styles=styles,
                                   noise=[1e-3])
            figures.accuracy_dots(summary, out / f"{group}_acc", metric="rmse", title=group, styles=styles,
                                  noise=[1e-3])
            one = rows[rows["difficulty"] == 1.0]
            figures.error_per_frame(one, out / f"{group}_epf", metric="rmse", title=group, styles=styles)
            figures.intensity_sums(one, out / f"{group}_sums", title=group, styles=styles)
            temporal = one.groupby("spec", sort=False).agg(
                method=("method", "first"), options=("options", "first"), label=("label", "first"),
                reference_noise_rmse=("reference_noise_rmse", "first")).reset_index()
            temporal["flicker"] = np.linspace(1e-3, 1e-2, len(temporal))
            temporal["temporal_bias"] = np.linspace(2e-3, 1e-3, len(temporal))
            temporal["group"] = group
            figures.temporal_bars(temporal, out / f"{group}_flicker", group=group, metrics=["temporal_bias", "flicker"],
                                  title=group, styles=styles)
            figures.stability(rows, out / f"{group}_stab", metric="rmse", failed=failed.loc[rows.index],
                              title=group, styles=styles, definition="A cell fails when ...")
        exact = results[results["method"].isin(["catmull", "weiler-atherton"])]
        figures.validation(exact.rename(columns={"reference_noise_rmse": "noise_rmse"}), out / "validation",
                           title="validation", styles=styles)
    finally:
        figures.save_figure = save
    return [(n, f) for n, f, _ in made], styles, {n: c for n, _, c in made}


def _tick_collisions(fig) -> list[str]:
    renderer = fig.canvas.get_renderer()
    found = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in axis.get_ticklabels()
                     if t.get_visible() and t.get_text()]
            found.extend(f"{text!r} is raw mathtext" for text, _ in boxes if "$" in text)
            for (ta, a), (tb, b) in itertools.combinations(boxes, 2):
                if min(a.x1, b.x1) - max(a.x0, b.x0) > 1 and min(a.y1, b.y1) - max(a.y0, b.y0) > 1:
                    found.append(f"{ta!r} and {tb!r}")
    return found


def _tagged(fig):
    for artist in fig.findobj(lambda a: (a.get_gid() or "").startswith("method=")):
        gid = artist.get_gid()
        method = gid.split(";", 1)[0][len("method="):]
        spec = gid if ";options=" in gid else None
        if isinstance(artist, Line2D):
            marker = artist.get_marker()
            yield method, spec, to_rgb(artist.get_color()), None if marker in ("None", "", None, " ") else marker
        elif isinstance(artist, Patch):
            yield method, spec, to_rgb(artist.get_facecolor()), None


def _hue(rgb) -> tuple[float, float]:
    h, _, s = colorsys.rgb_to_hls(*rgb)
    return h, s


def test_each_method_looks_the_same_in_every_figure(drawn):
    made, _, _ = drawn
    assert len(made) >= 6 * 9 + 1
    spec_looks: dict[str, set] = {}
    method_markers: dict[str, set] = {}
    method_hues: dict[str, list] = {}
    for _, fig in made:
        for method, spec, colour, marker in _tagged(fig):
            if spec is not None:
                spec_looks.setdefault(spec, set()).add(tuple(round(c, 4) for c in colour))
            if marker is not None:
                method_markers.setdefault(method, set()).add(marker)
            method_hues.setdefault(method, []).append(_hue(colour))
    assert set(method_markers) >= {"catmull", "weiler-atherton", "point", "supersample", "jitter", "abuffer",
                                   "skia", "catmull-jagged", "mitsuba"}
    for spec, colours in spec_looks.items():
        assert len(colours) == 1, f"{spec} drawn in {colours}"
    for method, markers in method_markers.items():
        assert markers == {method_style(method).marker}, (method, markers)
    for method, hues in method_hues.items():
        base_h, base_s = _hue(to_rgb(method_style(method).colour))
        for h, s in hues:
            if base_s > 0.1 and s > 0.1:  # greys (skia's black) have no hue
                # a method's family: ladders are shades of its hue, categorical choices turn it a little
                assert min(abs(h - base_h), 1 - abs(h - base_h)) < 0.1, (method, h, base_h)


def test_methods_differ_without_colour():
    # read in greyscale: marker and dash pattern alone tell every method apart
    markers = [s.marker for s in METHOD_STYLES.values()]
    dashes = [s.dashes for s in METHOD_STYLES.values()]
    assert len(set(markers)) == len(markers) and len(set(dashes)) == len(dashes)


def test_option_ladders_are_shades_in_value_order(drawn):
    _, styles, _ = drawn
    ks = [2, 4, 8, 16]
    shades = [styles.spec("supersample", {"k": k}).colour for k in ks]
    lightness = [colorsys.rgb_to_hls(*c)[1] for c in shades]
    assert lightness == sorted(lightness, reverse=True)  # light for the smallest k, dark for the largest
    order = sorted(ks[::-1], key=lambda k: styles.order("supersample", {"k": k}))
    assert order == ks


def test_legends_list_options_by_value(drawn):
    made, _, _ = drawn
    name, fig = next((n, f) for n, f in made if n == "speed-accuracy_speed")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    ladder = [lab for lab in labels if lab.startswith("supersample")]
    assert ladder == sorted(ladder, key=lambda s: int(s.split("k=")[1])), ladder
    spp = [int(lab.split("spp=")[1].split(",")[0]) for lab in labels if lab.startswith("mitsuba")]
    assert spp == sorted(spp) and len(spp) == 5


def test_tick_labels_do_not_collide(drawn):
    _, _, collisions = drawn
    for name, found in collisions.items():
        assert not found, f"{name}: tick labels overlap or show markup: {found}"


def test_a_figure_is_written_as_png_svg_and_pdf_with_its_style_tags(drawn, tmp_path_factory):
    made, _, _ = drawn
    assert SAVED in {name for name, _ in made}
    folder = next(iter(tmp_path_factory.getbasetemp().glob("style*")))
    for fmt in figures.FORMATS:
        assert (folder / f"{SAVED}.{fmt}").stat().st_size > 0, fmt
    svg = (folder / "validation.svg").read_text()
    assert 'id="method=catmull;options=' in svg and 'id="method=weiler-atherton;options=blend=linear,convex=True,window=0"' in svg  # the style tags survive into the SVG


def test_every_registered_method_has_its_own_line():
    # the fallback style is for methods registered by plugins at run time; the shipped ones
    # are in the table, so that none changes look when another method is added
    from aaeval.renderers import METHODS

    missing = sorted(set(METHODS) - set(METHOD_STYLES))
    assert not missing, f"add a line for {missing} to METHOD_STYLES in aaeval/report/style.py"


def test_every_method_and_clamp_has_a_colour_of_its_own():
    """Colours compared with each other (CIELAB distance), not with the style table:
    every registered method and every specular clamp of catmull, as one report would draw them."""
    import colorsys

    from skimage.color import rgb2lab

    from aaeval.renderers import METHODS, resolve
    from aaeval.specular.methods import SPECULAR_METHODS

    specs = [(m, json.dumps(resolve(m)[1])) for m in METHODS]
    specs += [("catmull", json.dumps(resolve(f"catmull:specular={s}")[1])) for s in SPECULAR_METHODS]
    styles = _styles(specs)
    colours = {(m, o): np.asarray(styles.spec(m, o).colour, float) for m, o in specs}
    lab = {k: rgb2lab(c[None, None, :])[0, 0] for k, c in colours.items()}
    for a, b in itertools.combinations(lab, 2):
        assert np.linalg.norm(lab[a] - lab[b]) > 15, (a, b)
    # the clamps stay in catmull's family: hues near each other, far from the other methods'
    hue = lambda c: colorsys.rgb_to_hls(*c)[0]  # noqa: E731
    clamps = [colours[("catmull", json.dumps(resolve(f"catmull:specular={s}")[1]))] for s in SPECULAR_METHODS]
    assert max(hue(c) for c in clamps) - min(hue(c) for c in clamps) < 0.15


def test_coincident_exact_methods_both_show():
    """Weiler-Atherton's points sit exactly on catmull's: it is drawn hollow, larger and above."""
    styles = _styles([("catmull", "{}"), ("weiler-atherton", "{}")])
    cat, wa = styles.spec("catmull", "{}"), styles.spec("weiler-atherton", "{}")
    assert wa.fillstyle == "none" and cat.fillstyle == "full" and wa.size > cat.size
    assert wa.line()["zorder"] > 2
