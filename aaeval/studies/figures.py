"""The figures of the studies: each paper's own pictures made again, written by ``aaeval study``
into ``experiments/NAME/figures/`` and shown in the README (a ``kind = "figure"`` summary names
one of :data:`FIGURES`).

Each figure renders what it shows (the scenes are small, or their frames few) with the
methods the paper compares and the truth beside them, and returns the markdown that shows it:
the image and the numbers it turns on, each computed here from the images drawn. Images are
linear RGB rendered, shown in sRGB, enlarged without smoothing (one block per pixel).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

__all__ = ["FIGURES", "Figure"]

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "configs" / "scenes"


@dataclass(frozen=True)
class Figure:
    """One study figure: what it shows, and ``draw(folder) -> markdown lines`` (``folder``: the
    study's ``figures/``, where it writes its PNGs)."""

    what: str
    draw: Callable[[Path], list[str]]


def _plt():
    from aaeval.report import figures  # the report's Agg backend and fonts

    return figures.plt


def _save(fig, folder: Path, stem: str) -> str:
    from aaeval.report.figures import save_figure

    path = save_figure(fig, folder / stem)
    return f"figures/{path.name}"


def _show(ax, image: np.ndarray, title: str = "") -> None:
    from aaeval.fileio import linear_to_srgb8

    ax.imshow(linear_to_srgb8(image), interpolation="nearest")
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=8)


def _frames(scene, spec: str, frames) -> np.ndarray:
    from aaeval.renderers import render

    return np.stack([render(scene, spec, frame=k) for k in frames])


def _scene(name: str):
    from aaeval.scenes import load_scene

    return load_scene(SCENES / name)


# --- Amanatides 1992: plates 2, 3, 4 ------------------------------------------------------

PLATES = (("catmull:shading=exact", "truth: exact shading"),
          ("catmull:specular=none", "plate 2: one shade per piece"),
          ("catmull:specular=amanatides", "plate 3: clamped"),
          ("catmull:specular=amanatides,power=0.999", "plate 4: clamped, 99.9% power"))
#: The window of the strip: rows and columns of cylinders.toml around the upper-right, very thin
#: cylinder (radius 2.5 px, facets 0.5 px wide), whose highlight pops as it moves; and the
#: 6 x 6 pixels inside it whose highlight light is followed frame by frame.
STRIP = (slice(0, 40), slice(196, 224))
PROBE = (slice(12, 18), slice(204, 210))
STRIP_FRAMES = tuple(range(8))
CURVE_FRAMES = tuple(range(16))


def _exact_frames(scene, frames) -> tuple[np.ndarray, np.ndarray]:
    """The exact shading of each of ``frames`` (the ``catmull:shading=exact`` images) and,
    subtracted from it, its specular term: the same integral without the highlights (the
    render with every ks = 0, to rounding), from the one integration."""
    from aaeval.specular.exact import exact_shading

    shaded = [exact_shading(scene.at_frame(k)) for k in frames]
    images = np.stack([s.image for s in shaded])
    return images, images - np.stack([s.specular for s in shaded])[..., None]  # the specular term is white


def _strip_window(scene):
    """``scene`` seen through :data:`STRIP`."""
    rows, cols = STRIP
    return scene.window(cols.start, rows.start, cols.stop - cols.start, rows.stop - rows.start)


def amanatides_plates(folder: Path) -> list[str]:
    scene = _scene("shaded/cylinders.toml")
    plt = _plt()
    images = [_frames(scene, spec, [0])[0] for spec, _ in PLATES]
    fig, axes = plt.subplots(1, 4, figsize=(11.6, 3.1))  # each panel about 270 px: the plates' 256 at full size
    fig.subplots_adjust(left=0.005, right=0.995, bottom=0.01, top=0.9, wspace=0.04)
    for ax, image, (_, title) in zip(axes, images, PLATES):
        _show(ax, image, title)
    plates = _save(fig, folder, "plates")
    # the strip: the thin cylinder over frames, each method's row; beside it the highlight's light
    # in the probe (the image less the exact render with the specular term off) over the truth's
    # only the strip's window is rendered: its pixels are the full render's crop
    truth, dull = _exact_frames(_strip_window(scene), CURVE_FRAMES)  # the first plate's row: the truth
    rows = [truth] + [_frames(_strip_window(scene), spec, CURVE_FRAMES) for spec, _ in PLATES[1:]]
    probe = tuple(slice(p.start - w.start, p.stop - w.start) for p, w in zip(PROBE, STRIP))
    light = [(frames - dull)[:, probe[0], probe[1]].sum(axis=(1, 2, 3)) for frames in rows]
    ratio = [e / light[0] for e in light]
    fig, axes = plt.subplots(len(PLATES), len(STRIP_FRAMES) + 1, figsize=(12, 8.4),
                             gridspec_kw={"width_ratios": [1] * len(STRIP_FRAMES) + [3.0]})
    from matplotlib.colors import PowerNorm
    from matplotlib.patches import Rectangle

    # the highlight alone (the image less the render without it), on one square-root scale for
    # every panel: a thin bright line and a dim broken one both show
    highlights = [(frames - dull).mean(axis=-1) for frames in rows]
    norm = PowerNorm(0.5, vmin=0.0, vmax=max(float(h[list(STRIP_FRAMES)].max()) for h in highlights))
    for r, (frames, (_, title)) in enumerate(zip(highlights, PLATES)):
        for k in STRIP_FRAMES:
            ax = axes[r, k]
            ax.imshow(np.clip(frames[k], 0.0, None), cmap="magma", norm=norm, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if r == 0:
                ax.set_title(f"frame {k}", fontsize=8)
            ax.add_patch(Rectangle((PROBE[1].start - STRIP[1].start - 0.5, PROBE[0].start - STRIP[0].start - 0.5),
                                   PROBE[1].stop - PROBE[1].start, PROBE[0].stop - PROBE[0].start, fill=False,
                                   edgecolor="yellow", lw=0.8))
        axes[r, 0].set_ylabel(title.split(":")[0], fontsize=8)
        ax = axes[r, -1]
        ax.plot(CURVE_FRAMES, ratio[r], marker="o", ms=3, color="black")
        ax.axhline(1.0, color="0.6", lw=0.8)
        ax.set_ylim(0.0, 1.2)
        ax.set_title("highlight light in the yellow box / truth's" if r == 0 else "", fontsize=8)
        ax.set_xlabel("frame" if r == len(PLATES) - 1 else "", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.yaxis.tick_right()  # clear of the last frame's panel
    strip = _save(fig, folder, "highlight_strip")
    spread = ", ".join(f"{title.split(':')[0]} {float(r.min()):.3f} to {float(r.max()):.3f}"
                       for r, (_, title) in zip(ratio[1:], PLATES[1:]))
    return [f"![Plates 2-4 of cylinders.toml at 256 x 256 beside the exact shading]({plates})", "",
            "Frame 0 of `configs/scenes/shaded/cylinders.toml` (256 x 256, Phong n = 1000, lit from behind the "
            "viewer), left to right: the exact shading (the truth), one shade per visible piece (plate 2), "
            "Amanatides' clamp (plate 3) and the clamp at 99.9% power (plate 4).", "",
            f"![The thin upper-right cylinder's highlight over frames]({strip})", "",
            f"The very thin upper-right cylinder (rows {STRIP[0].start}-{STRIP[0].stop - 1}, columns "
            f"{STRIP[1].start}-{STRIP[1].stop - 1}) in frames {STRIP_FRAMES[0]}-{STRIP_FRAMES[-1]}, one row per "
            "method, the highlight alone (each image less the exact render with the specular term off, on one "
            "square-root colour scale); right: the highlight's light in the yellow box over the truth's, "
            f"frames {CURVE_FRAMES[0]}-{CURVE_FRAMES[-1]}. A steady method draws "
            "a flat line (at 1 if unbiased); popping is a line that jumps. Its range over the frames: "
            f"{spread}."]


# --- Catmull 1978: the picket fence and figure 1 ------------------------------------------

FENCE_WINDOW = (slice(0, 8), slice(4, 10))


def catmull_fence(folder: Path) -> list[str]:
    scene = _scene("picket_fence.toml")
    plt = _plt()
    frames = range(scene.frames)
    specs = (("point", "point"), ("supersample:k=4", "supersample 4x4"), ("catmull", "exact (catmull)"))
    images = {spec: _frames(scene, spec, frames) for spec, _ in specs}
    fig = plt.figure(figsize=(12, 6.2))
    grid = fig.add_gridspec(3, 16, height_ratios=[1.3, 1.3, 2.2], hspace=0.3)
    for r, spec in enumerate(("point", "catmull")):
        for k in frames:
            ax = fig.add_subplot(grid[r, k])
            _show(ax, images[spec][k][FENCE_WINDOW], f"{k}" if r == 0 else "")
            if k == 0:
                ax.set_ylabel(spec if spec == "point" else "exact", fontsize=8)
    ax = fig.add_subplot(grid[2, :])
    sums = {spec: images[spec].sum(axis=(1, 2, 3)) for spec, _ in specs}
    for (spec, label), marker in zip(specs, "osx"):
        ax.plot(list(frames), sums[spec], marker=marker, ms=4, label=label)
    ax.set_xlabel("frame (the fence moves 1/16 px per frame)")
    ax.set_ylabel("intensity sum")
    ax.legend(fontsize=7)
    path = _save(fig, folder, "fence")
    line = ", ".join(f"{label} {_range(sums[spec])}" for spec, label in specs)
    return [f"![The picket fence, point sampling against the exact box filter, and the sum per frame]({path})", "",
            f"Columns {FENCE_WINDOW[1].start}-{FENCE_WINDOW[1].stop - 1} of the fence (0.3 px bars, one per pixel) in frames 0-15, point sampling (top) and the "
            f"exact box filter (middle), and every frame's intensity sum (bottom): {line}."]


def _range(values: np.ndarray) -> str:
    lo, hi = float(values.min()), float(values.max())
    return f"{lo:.6g}" if np.isclose(lo, hi, rtol=1e-12, atol=1e-12) else f"{lo:.6g} to {hi:.6g}"


def catmull_figure1(folder: Path) -> list[str]:
    from matplotlib.patches import Polygon as Patch

    scene = _scene("catmull_fig1.toml")
    plt = _plt()
    specs = (("catmull", "exact (catmull)"), ("catmull-jagged", "catmull-jagged"), ("point", "point"),
             ("supersample:k=4", "supersample 4x4"))
    fig, axes = plt.subplots(1, len(specs) + 1, figsize=(12, 2.9))
    ax = axes[0]
    for poly in sorted(scene.polygons, key=lambda p: -float(np.mean(np.asarray(p.vertices)[:, 2]))):  # far first
        ax.add_patch(Patch(np.asarray(poly.vertices)[:, :2], closed=True, facecolor=np.clip(poly.color, 0, 1),
                           edgecolor="white", lw=0.6))
    for poly in scene.polygons:  # every outline on top, dashed: the hidden red one too
        ax.add_patch(Patch(np.asarray(poly.vertices)[:, :2], closed=True, fill=False, linestyle="--", lw=1.0,
                           edgecolor=np.clip(poly.color, 0, 1)))
    ax.set_xlim(1, 2)
    ax.set_ylim(2, 1)
    ax.set_aspect("equal")
    ax.set_facecolor("black")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("pixel (1, 1): polygons far first, outlines dashed", fontsize=8)
    values = []
    for ax, (spec, label) in zip(axes[1:], specs):
        pixel = _frames(scene, spec, [0])[0][1:2, 1:2]
        values.append((label, pixel[0, 0]))
        _show(ax, pixel, label)
    path = _save(fig, folder, "figure1_pixel")
    return [f"![Figure 1's pixel enlarged, as each method renders it]({path})", "",
            "Figure 1's pixel (row 1, column 1 of `configs/scenes/catmull_fig1.toml`) enlarged: its polygons drawn "
            "far to near with every outline dashed on top (the red one is hidden by green and blue together), then the one colour each method gives the pixel (linear RGB): "
            + "; ".join(f"{label} ({', '.join(f'{v:.3f}' for v in value)})" for label, value in values) + "."]


# --- Khan: figures 1-4 ----------------------------------------------------------------------

KHAN = (("rectangles", "figure 1, rectangles"), ("triangles", "figure 2, triangles"),
        ("monochrome", "figure 3, monochrome shapes"), ("concave", "figure 4, concave shapes"))


def khan_figures(folder: Path) -> list[str]:
    plt = _plt()
    fig, axes = plt.subplots(len(KHAN), 4, figsize=(8.4, 8.8))
    for r, (name, title) in enumerate(KHAN):
        for c, (order, spec, label) in enumerate((("a", "point", "(a) without: point"),
                                                   ("a", "catmull", "(b) with: exact"),
                                                   ("b", "point", "other depth order, point"),
                                                   ("b", "catmull", "other depth order, exact"))):
            image = _frames(_scene(f"khan_{name}_{order}.toml"), spec, [0])[0]
            _show(axes[r, c], image, label if r == 0 else "")
        axes[r, 0].set_ylabel(title, fontsize=8)
    path = _save(fig, folder, "khan_figures")
    return [f"![Khan's figures 1-4, without and with area-weighted pixels, in both depth orders]({path})", "",
            "Khan's four figures (`configs/scenes/khan_*_a.toml` and `_b.toml`, 32 x 32), each rendered as her "
            "\"(a) without the proposed method\" (point sampling: one colour per pixel) and as the exact box filter "
            "her \"(b)\" approximates, in the figure's depth order and with the depths swapped."]


# --- Weiler-Atherton 1977: visible polygons and hidden lines --------------------------------

WA_SCENES = ("interpenetrating.toml", "khan_concave_a.toml", "khan_concave_b.toml", "fan.toml")


def weiler_atherton_drawings(folder: Path) -> list[str]:
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MPath

    from aaeval.weiler_atherton.hidden_surface import visible_pieces
    from aaeval.weiler_atherton.lines import visible_edges

    plt = _plt()
    fig, axes = plt.subplots(2, len(WA_SCENES), figsize=(12, 6.4))
    counts = []
    for c, name in enumerate(WA_SCENES):
        scene = _scene(name)
        pieces = visible_pieces(scene)
        top, bottom = axes[0, c], axes[1, c]
        for piece in pieces:
            vertices, codes = [], []
            for ring in piece.shape.rings:  # holes are rings of their own: a compound path
                vertices += [*ring, ring[0]]
                codes += [MPath.MOVETO] + [MPath.LINETO] * (len(ring) - 1) + [MPath.CLOSEPOLY]
            colour = np.clip(scene.polygons[piece.source].color, 0, 1)
            top.add_patch(PathPatch(MPath(vertices, codes), facecolor=colour, edgecolor="black", lw=0.5))
        edges = visible_edges(scene)
        for p, q, _ in edges:
            bottom.plot([p[0], q[0]], [p[1], q[1]], color="black", lw=0.8)
        for ax in (top, bottom):
            ax.set_xlim(0, scene.width)
            ax.set_ylim(scene.height, 0)
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
        top.set_title(f"{Path(name).stem}: {len(pieces)} visible pieces", fontsize=8)
        bottom.set_title(f"hidden lines removed: {len(edges)} segments", fontsize=8)
        counts.append((Path(name).stem, len(scene.polygons), len(pieces), len(edges)))
    path = _save(fig, folder, "visible_polygons")
    return [f"![Weiler-Atherton's visible polygons and hidden-line drawings]({path})", "",
            "Top: the visible polygons Weiler-Atherton's area sort leaves (each piece outlined, holes as holes); "
            "bottom: the same scenes as hidden-line drawings (the visible edges). Polygons, visible pieces, "
            "visible segments: " + "; ".join(f"`{s}` {n}, {p}, {e}" for s, n, p, e in counts) + "."]


#: Figures a study.toml may name (``kind = "figure"``, ``figure = NAME``).
FIGURES: dict[str, Figure] = {
    "amanatides-plates": Figure("plates 2-4 of cylinders.toml beside the truth, and the highlight over frames",
                                amanatides_plates),
    "catmull-fence": Figure("the picket fence's frames, point against exact, and the sum per frame", catmull_fence),
    "catmull-figure1": Figure("figure 1's pixel enlarged, as each method renders it", catmull_figure1),
    "khan-figures": Figure("Khan's figures 1-4, point and exact, both depth orders", khan_figures),
    "weiler-atherton-drawings": Figure("visible polygons and hidden-line drawings", weiler_atherton_drawings),
}
