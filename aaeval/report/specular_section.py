"""The specular study's section of the report: Amanatides 1992 against Mitsuba's Phong truth.

What it shows, every image against the Mitsuba Phong ground truth
(:mod:`aaeval.groundtruth.phong`, the same formula at every sample, box filter), whose
spp, sampler and seed are stated with its noise (seed 1 against seed 0):

- Amanatides' tables (his figures 2 and 3): the power cutoff of cos^n, and what clamping
  with renormalisation does to the lobe's cosine components;
- the plates (his plates 2-5): the shipped scenes ``configs/scenes/shaded/*.toml`` at frame
  0 under every specular method registered in :mod:`aaeval.specular.methods` (and
  Amanatides' aggressive P = 0.999), with a zoom on the brightest highlight and its
  signed error;
- detection maps: where Amanatides' test flags a pixel, and its oversampling rate;
- highlight error and flicker over the first frames of the animated plate: per-frame
  RMSE over the highlight (truth specular term above :data:`HIGHLIGHT_THRESHOLD`), the
  specular energy of a cross-section of the brightest highlight per frame against the
  truth's (where a highlight that breaks up under sub-pixel motion flickers), and a table.

The section appears when the sweep in ``out_dir`` has scenes with ``[shaded]`` objects
(its manifest's scene documents say so) or when asked (``force=True``); otherwise it is
empty, so reports of flat sweeps cost nothing more. Ground truths come from the one
ground-truth cache, so a second report renders only aaeval's methods.
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import NamedTuple, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import SymLogNorm  # noqa: E402
from scipy.special import gammaln  # noqa: E402

import aaeval  # noqa: E402
from aaeval.groundtruth import DEFAULT_SAMPLER, groundtruth  # noqa: E402
from aaeval.imageio import linear_to_srgb8  # noqa: E402
from aaeval.renderers import resolve  # noqa: E402
from aaeval.report.figures import save_figure  # noqa: E402  (PNG + SVG + PDF, as every report figure)
from aaeval.report.style import SpecStyle, Styles, ground_truth_style  # noqa: E402
from aaeval.scenes import Scene, load_scene  # noqa: E402
from aaeval.specular.methods import SPECULAR_METHODS  # noqa: E402
from aaeval.specular.render import render_shaded, specular_aliasing_map  # noqa: E402
from aaeval.specular.tables import cutoff_table, maximum  # noqa: E402

__all__ = ["specular_section", "SECTION_SPP", "SECTION_FRAMES", "HIGHLIGHT_THRESHOLD", "plate_scenes"]

# Ground-truth samples per pixel (a square, which every sampler keeps as is); the measured
# noise (seed 1 vs 0) is printed beside it.
SECTION_SPP = 256
# Frames of the animated plate over which highlight error and flicker are measured.
SECTION_FRAMES = 8
# A pixel belongs to the highlight where the truth's specular term exceeds this.
HIGHLIGHT_THRESHOLD = 0.02


class _Method(NamedTuple):
    label: str
    options: dict  # render_shaded's keywords

    def style(self, styles: Styles) -> SpecStyle:
        return styles.spec("catmull", _full_options(self.label))


def _full_options(label: str) -> dict:
    # the options the results table records for this spec: every declared one, defaults filled in
    return resolve(label)[1]


def _methods() -> list[_Method]:
    """Every registered specular method, and Amanatides' aggressive table (P = 0.999)."""
    out = []
    for name in SPECULAR_METHODS:
        out.append(_Method(f"catmull:specular={name}", {"specular": name}))
        if name == "amanatides":
            out.append(_Method("catmull:specular=amanatides,power=0.999", {"specular": name, "power": 0.999}))
    return out


def _styles(methods: list[_Method]) -> dict[str, SpecStyle]:
    """Each method's look from the report's one style table (same as in the group figures)."""
    styles = Styles(("catmull", _full_options(m.label)) for m in methods)
    return {m.label: m.style(styles) for m in methods}


def plate_scenes() -> list[Path]:
    """The shipped plates (``configs/scenes/shaded/*.toml`` of the source tree), if present;
    the cylinders first (Amanatides' plates 2-4, the animated scene of the measurements)."""
    folder = Path(aaeval.__file__).parents[1] / "configs" / "scenes" / "shaded"
    found = sorted(folder.glob("*.toml")) if folder.is_dir() else []
    return sorted(found, key=lambda p: (p.stem != "cylinders", p.stem))


def specular_section(
    out_dir: Path,
    figures_dir: Path,
    *,
    force: bool = False,
    scenes: Sequence[Path] | None = None,
    spp: int = SECTION_SPP,
    frames: int = SECTION_FRAMES,
) -> str:
    """HTML fragment of the specular study for the report of the sweep in ``out_dir``.

    Figures are written into ``figures_dir`` as PNG, SVG and PDF (as every report figure); the fragment refers to them
    relative to ``out_dir`` (where the report's ``index.html`` lives). Empty when the
    sweep has no ``[shaded]`` scenes, unless ``force``. ``scenes`` replaces the shipped
    plates (the first one is also the animated scene of the flicker measurement).
    """
    out_dir, figures_dir = Path(out_dir), Path(figures_dir)
    if not (force or _sweep_has_shaded_scenes(out_dir)):
        return ""
    paths = list(plate_scenes() if scenes is None else scenes)
    if not paths:
        return ("<h2 id='specular'>Specular aliasing</h2><p>The plate scenes (configs/scenes/shaded/) are not "
                "in this installation; nothing to show.</p>")
    figures_dir.mkdir(parents=True, exist_ok=True)
    methods = _methods()
    colours = _styles(methods)
    truth_of = _TruthCache(spp)
    first = load_scene(paths[0]).at_frame(0)
    section = _cross_section(truth_of(first).specular)
    noise = truth_of.noise(first, section)

    parts = [
        "<h2 id='specular'>Specular aliasing (Amanatides 1992)</h2>",
        f"<p class='note'>Reference: the Mitsuba Phong ground truth (the same Phong formula at every sample, "
        f"box filter), {spp} spp, {html.escape(DEFAULT_SAMPLER)} sampler, seed 0. Its noise, measured as seed 1 "
        f"against seed 0 on {html.escape(paths[0].stem)} frame 0: image RMSE {noise.image:.2e}, highlight RMSE "
        f"{noise.highlight:.2e}. Methods: the Catmull renderer (exact visibility, one shade per visible piece "
        f"of a polygon in a pixel) under every registered specular method. Highlight: pixels where the truth's "
        f"specular term exceeds {HIGHLIGHT_THRESHOLD}.</p>",
    ]
    rel = _relative_to(figures_dir, out_dir)
    parts.append(_figure(rel, _fig_power_cutoff(figures_dir),
                         "Amanatides' figure 2: frequency below which a fraction of the power of cos^n lies."))
    parts.append(_figure(rel, _fig_clamp_ratio(figures_dir),
                         "Amanatides' figure 3: cosine components of cos^160 clamped to n' and renormalised by "
                         "Maximum[160]/Maximum[n'], over those of cos^160."))
    for path in paths:
        scene = load_scene(path).at_frame(0)
        truth = truth_of(scene)
        images = [(m.label, render_shaded(scene, **m.options)) for m in methods]
        name = _slug(path.stem)
        parts.append(_figure(rel, _fig_plate(figures_dir / f"specular_plate_{name}", path.stem, truth.image,
                                             truth.specular, images, spp, noise),
                             f"{path.stem}, frame 0: each specular method, a zoom on the brightest highlight and "
                             f"its signed error against the truth ({spp} spp)."))
    detect = load_scene(paths[0]).at_frame(0)
    parts.append(_figure(rel, _fig_detection(figures_dir / f"specular_detection_{_slug(paths[0].stem)}", detect),
                         f"{paths[0].stem}, frame 0: Amanatides' detection (conservative and P = 0.999) and the "
                         f"largest normal turn per pixel."))
    animated = load_scene(paths[0])
    series = _over_frames(animated, min(frames, animated.frames), methods, truth_of, section)
    slug = _slug(paths[0].stem)
    parts.append(_figure(rel, _fig_highlight_error(figures_dir / f"specular_highlight_error_{slug}", series,
                                                   colours, noise),
                         f"{paths[0].stem}: highlight RMSE per frame against the truth; the band is the truth's own "
                         f"noise."))
    parts.append(_figure(rel, _fig_energy(figures_dir / f"specular_energy_{slug}", series, colours, spp, noise,
                                          section),
                         f"{paths[0].stem}: specular energy of a cross-section of the brightest highlight "
                         f"({section.describe()}) per frame; flicker is what a method's curve does that the truth's "
                         f"does not (grey: the truth's noise, seed 1 vs 0)."))
    parts.append(_summary_table(series, noise))
    return "\n".join(parts)


# --- which sweeps get the section -----------------------------------------------------


def _sweep_has_shaded_scenes(out_dir: Path) -> bool:
    try:
        manifest = json.loads((out_dir / "manifest.json").read_text())
    except (OSError, ValueError):
        return False
    scenes = manifest.get("scenes") if isinstance(manifest, dict) else None
    if not isinstance(scenes, dict):
        return False
    return any(isinstance(s, dict) and isinstance(s.get("document"), dict) and "shaded" in s["document"]
               for s in scenes.values())


# --- the ground truth, its noise, and measurements over frames -------------------------


class _Noise(NamedTuple):
    image: float  # RMSE of the truth's seed 1 against seed 0
    highlight: float  # the same over the highlight pixels
    energy: float  # |difference| of the cross-section's specular energy


class _Section(NamedTuple):
    """A one-pixel-wide cut across the brightest highlight: ``rows`` x ``cols`` slices."""

    rows: slice
    cols: slice

    def describe(self) -> str:
        if self.rows.stop - self.rows.start == 1:
            return f"row {self.rows.start}, columns {self.cols.start}-{self.cols.stop - 1}"
        return f"column {self.cols.start}, rows {self.rows.start}-{self.rows.stop - 1}"

    def energy(self, specular: np.ndarray) -> float:
        return float(specular[self.rows, self.cols].sum())


def _cross_section(specular: np.ndarray, half: int = 24) -> _Section:
    """The row or column segment through the brightest pixel that crosses the highlight
    (the one with fewer highlight pixels: across it, not along it)."""
    h, w = specular.shape
    r, c = np.unravel_index(int(np.argmax(specular)), specular.shape)
    row = _Section(slice(r, r + 1), slice(max(c - half, 0), min(c + half + 1, w)))
    col = _Section(slice(max(r - half, 0), min(r + half + 1, h)), slice(c, c + 1))
    lit = [int((specular[s.rows, s.cols] > HIGHLIGHT_THRESHOLD).sum()) for s in (row, col)]
    return row if lit[0] <= lit[1] else col


class _TruthCache:
    """Ground truths of this section (seed 0), each read or rendered once."""

    def __init__(self, spp: int):
        self.spp = spp
        self._seen: dict[tuple[str, int, int], object] = {}

    def __call__(self, scene: Scene, seed: int = 0):
        key = (scene.source, scene.frame, seed)
        if key not in self._seen:
            self._seen[key] = groundtruth(scene, spp=self.spp, seed=seed)
        return self._seen[key]

    def noise(self, scene: Scene, section: _Section) -> _Noise:
        a, b = self(scene, 0), self(scene, 1)
        mask = a.specular > HIGHLIGHT_THRESHOLD
        return _Noise(_rmse(a.image, b.image), _rmse(a.image[mask], b.image[mask]),
                      abs(section.energy(a.specular) - section.energy(b.specular)))


def _rmse(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((np.asarray(a) - np.asarray(b)) ** 2))) if np.size(a) else float("nan")


class _Series(NamedTuple):
    frames: list[int]
    truth_energy: np.ndarray  # (F,) specular energy of the cross-section
    energy: dict[str, np.ndarray]  # label -> (F,)
    highlight_rmse: dict[str, np.ndarray]  # label -> (F,)


def _over_frames(scene: Scene, count: int, methods: list[_Method], truth_of: _TruthCache,
                 section: _Section) -> _Series:
    frames = list(range(count))
    truth_energy = np.zeros(count)
    energy = {m.label: np.zeros(count) for m in methods}
    error = {m.label: np.zeros(count) for m in methods}
    for k in frames:
        at = scene.at_frame(k)
        truth = truth_of(at)
        mask = truth.specular > HIGHLIGHT_THRESHOLD
        truth_energy[k] = section.energy(truth.specular)
        for m in methods:
            image, specular = render_shaded(at, return_specular=True, **m.options)
            energy[m.label][k] = section.energy(specular)
            error[m.label][k] = _rmse(image[mask], truth.image[mask])
    return _Series(frames, truth_energy, energy, error)


def flicker(energy: np.ndarray, truth_energy: np.ndarray) -> float:
    """RMS over frames of the energy error with its mean removed, over the truth's mean energy.

    A steady bias (a dimmer highlight in every frame) is not flicker; what changes from
    frame to frame and is not in the truth is.
    """
    error = np.asarray(energy) - np.asarray(truth_energy)
    return float(np.sqrt(np.mean((error - error.mean()) ** 2)) / np.mean(truth_energy))


# --- figures --------------------------------------------------------------------------


def _fig_power_cutoff(figures_dir: Path) -> Path:
    n_max = 1000
    n = np.arange(n_max + 1)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(n, n, "k:", lw=1, label="100 % (highest frequency n)")
    for power in (0.9999, 0.999, 0.99, 0.9):
        ax.plot(n, cutoff_table(n_max, power), label=f"{100 * power:g} % of the power")
    ax.plot([500, 500], [40, 52], "ko", ms=4)
    ax.annotate("n = 500: 52 (99.9 %), 40 (99 %)", (500, 52), (520, 150), arrowprops={"arrowstyle": "-"})
    ax.set(xlabel="n (highest frequency of cos^n)", ylabel="cutoff frequency", ylim=(0, 250),
           title="Power cutoff of cos^n (Amanatides 1992, fig. 2)")
    ax.legend(fontsize=8)
    return save_figure(fig, figures_dir / "specular_fig2_power_cutoff")


def cosine_amplitudes(n: int, m: np.ndarray) -> np.ndarray:
    """Amplitude of cos(m x) in cos^n x (0 where m > n or parities differ)."""
    ok = (m <= n) & ((n - m) % 2 == 0)
    k = (n - m[ok]) // 2
    amp = np.zeros(len(m))
    amp[ok] = np.exp(gammaln(n + 1) - gammaln(k + 1) - gammaln(n - k + 1) - n * np.log(2.0))
    amp[ok & (m > 0)] *= 2
    return amp


def _fig_clamp_ratio(figures_dir: Path) -> Path:
    n = 160
    m = np.arange(0, 81, 2)
    base = cosine_amplitudes(n, m)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for n_clamped in range(20, 141, 20):
        ratio = maximum(n) / maximum(n_clamped) * cosine_amplitudes(n_clamped, m) / base
        ax.plot(m, ratio, marker=".", label=f"n' = {n_clamped}")
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set(xlabel="frequency", ylabel="clamped / original component", ylim=(0, 1.2),
           title="cos^160 clamped to n', renormalised by Maximum[n]/Maximum[n'] (fig. 3)")
    ax.legend(fontsize=8, ncol=2)
    return save_figure(fig, figures_dir / "specular_fig3_clamp_ratio")


def _zoom_box(specular: np.ndarray, size: int = 48) -> tuple[slice, slice]:
    """A ``size`` x ``size`` window (clipped to the image) centred on the brightest highlight."""
    h, w = specular.shape
    r, c = np.unravel_index(int(np.argmax(specular)), specular.shape)
    sh, sw = min(size, h), min(size, w)
    r0 = int(np.clip(r - sh // 2, 0, h - sh))
    c0 = int(np.clip(c - sw // 2, 0, w - sw))
    return slice(r0, r0 + sh), slice(c0, c0 + sw)


def _fig_plate(stem: Path, name: str, truth: np.ndarray, truth_specular: np.ndarray, images, spp: int,
               noise: _Noise) -> Path:
    rows, cols = _zoom_box(truth_specular)
    panels = [("Mitsuba Phong (truth)", truth)] + list(images)
    errors = [np.abs((image - truth)[rows, cols].mean(axis=2)).max() for _, image in images]
    limit = max(max(errors, default=0.0), 1e-6)
    # one scale for all, logarithmic beyond the truth's noise: small errors stay visible
    norm = SymLogNorm(linthresh=min(max(noise.image, 1e-4), limit), vmin=-limit, vmax=limit)
    fig, axes = plt.subplots(3, len(panels), figsize=(2.0 * len(panels), 6.6), layout="constrained", squeeze=False)
    im = None
    for j, (label, image) in enumerate(panels):
        axes[0, j].imshow(linear_to_srgb8(image))
        axes[0, j].set_title(label.replace("catmull:", "").replace(",", ",\n"), fontsize=7)
        axes[1, j].imshow(linear_to_srgb8(image[rows, cols]), interpolation="nearest")
        error = (image - truth)[rows, cols].mean(axis=2)
        im = axes[2, j].imshow(error, cmap="RdBu_r", norm=norm, interpolation="nearest")
        axes[2, j].set_title(f"image RMSE {_rmse(image, truth):.2e}" if j else "truth (error 0)", fontsize=7)
    for ax in axes.ravel():
        ax.set_xticks([])
        ax.set_yticks([])
    axes[1, 0].set_ylabel(f"zoom rows {rows.start}-{rows.stop}, cols {cols.start}-{cols.stop}", fontsize=7)
    axes[2, 0].set_ylabel("signed error, mean of RGB\n(log beyond the truth noise)", fontsize=7)
    ticks = [-limit, -norm.linthresh, 0.0, norm.linthresh, limit]
    fig.colorbar(im, ax=axes[2, :], shrink=0.8, fraction=0.02, ticks=ticks, format="%.0e")
    fig.suptitle(f"{name}, frame 0, against Mitsuba Phong at {spp} spp {DEFAULT_SAMPLER}, seed 0 "
                 f"(its noise: image RMSE {noise.image:.1e})", fontsize=9)
    return save_figure(fig, stem)


def _fig_detection(stem: Path, scene: Scene) -> Path:
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.8), layout="constrained")
    for ax, power in zip(axes[:2], (1.0, 0.999)):
        found = specular_aliasing_map(scene, power=power)
        im = ax.imshow(np.log2(np.maximum(found.rate, 1e-3)), cmap="magma", vmin=-4, vmax=8, interpolation="nearest")
        if found.flag.any():
            ax.contour(found.flag, levels=[0.5], colors="c", linewidths=0.5)
        ax.set_title(f"log2 oversampling rate, power {power} (cyan: flagged)", fontsize=8)
        fig.colorbar(im, ax=ax, fraction=0.046)
    found = specular_aliasing_map(scene)
    im = axes[2].imshow(np.degrees(np.arccos(found.dot)), cmap="viridis", interpolation="nearest")
    axes[2].set_title("largest normal turn in the pixel (degrees)", fontsize=8)
    fig.colorbar(im, ax=axes[2], fraction=0.046)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    return save_figure(fig, stem)


def _fig_highlight_error(stem: Path, series: _Series, colours, noise: _Noise) -> Path:
    fig, ax = plt.subplots(figsize=(7.2, 4.0))
    values = np.concatenate([v for v in series.highlight_rmse.values()] + [[noise.highlight]])
    positive = values[values > 0]
    floor = float(positive.min()) / 2 if positive.size else 1e-9
    ax.axhspan(floor, max(noise.highlight, floor), color="0.85", label="truth noise (seed 1 vs 0)")
    for label, values in series.highlight_rmse.items():
        ax.plot(series.frames, values, label=label.replace("catmull:", ""), **colours[label].line())
    ax.set_yscale("log")
    ax.set(xlabel="frame", ylabel="highlight RMSE (linear RGB, log scale)", ylim=(floor, None),
           title="Highlight error per frame against Mitsuba Phong")
    ax.set_xticks(series.frames)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return save_figure(fig, stem)


def _fig_energy(stem: Path, series: _Series, colours, spp: int, noise: _Noise, section: _Section) -> Path:
    fig, ax = plt.subplots(figsize=(7.2, 4.0))
    ax.fill_between(series.frames, series.truth_energy - noise.energy, series.truth_energy + noise.energy,
                    color="0.8", lw=0)
    ax.plot(series.frames, series.truth_energy, label=f"Mitsuba Phong (truth, {spp} spp)", **ground_truth_style())
    for label, values in series.energy.items():
        ax.plot(series.frames, values, label=label.replace("catmull:", ""), **colours[label].line())
    ax.set(xlabel="frame", ylabel="specular energy of the cross-section",
           title=f"Highlight cross-section ({section.describe()}) per frame")
    ax.set_xticks(series.frames)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return save_figure(fig, stem)


# --- HTML -----------------------------------------------------------------------------


def _summary_table(series: _Series, noise: _Noise) -> str:
    head = ("<table><tr><th>method</th><th>highlight RMSE, mean over frames</th>"
            "<th>cross-section energy bias (relative)</th><th>flicker (relative)</th></tr>")
    mean_truth = float(np.mean(series.truth_energy))
    rows = []
    for label in series.energy:
        bias = float(np.mean(series.energy[label]) / mean_truth - 1.0)
        rows.append(f"<tr><td>{html.escape(label)}</td><td class='num'>{np.mean(series.highlight_rmse[label]):.3e}</td>"
                    f"<td class='num'>{bias:+.3f}</td>"
                    f"<td class='num'>{flicker(series.energy[label], series.truth_energy):.3e}</td></tr>")
    note = (f"<p>Over frames {series.frames[0]}-{series.frames[-1]}. Energy: the specular term summed over the "
            f"highlight's cross-section. Flicker: RMS over frames of the energy error with its mean removed, over "
            f"the truth's mean energy (a steady bias is not flicker). The truth's own noise: highlight RMSE "
            f"{noise.highlight:.2e}, cross-section energy {noise.energy / mean_truth:.1e} relative.</p>")
    return head + "".join(rows) + "</table>" + note


def _figure(rel: str, png: Path, caption: str) -> str:
    src = f"{rel}/{png.name}" if rel else png.name
    svg = src[:-4] + ".svg"
    return (f"<figure><img src='{html.escape(src)}' alt='{html.escape(caption[:120])}' style='max-width:100%'>"
            f"<figcaption>{html.escape(caption)} <a href='{html.escape(svg)}'>SVG</a></figcaption></figure>")


def _relative_to(folder: Path, root: Path) -> str:
    try:
        return folder.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return folder.resolve().as_uri()


def _slug(text: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in text).strip("_") or "scene"
