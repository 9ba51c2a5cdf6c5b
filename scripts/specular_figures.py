"""Figures of the specular anti-aliasing study (Amanatides 1992), as PNGs in reports/specular/.

- ``fig2_power_cutoff.png``: frequency below which a fraction of cos^n's power lies,
  against n (the paper's figure 2);
- ``fig3_clamp_ratio.png``: cosine components of the clamped, renormalised lobe
  (Ks Maximum[160]/Maximum[n'] cos^n') over those of cos^160, n' = 20..140 (figure 3);
- ``plates_cylinders.png`` / ``plates_cones.png``: the ground truth next to every specular
  option, with signed error maps (plates 2-5), and a zoom on the large highlight;
- ``detection_cylinders.png``: Amanatides' flag and oversampling rate per pixel;
- ``highlight_flicker.png``: energy of one cross-section of a highlight per frame, against
  the truth's (the flicker a viewer sees as the highlight breaks up).

Usage: ``PYTHONPATH=.:scripts python scripts/specular_figures.py [--spp S] [--quiet]``
(the ground truth comes from the on-disk cache when the experiment has run).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.special import gammaln  # noqa: E402

from aaeval.imageio import linear_to_srgb8  # noqa: E402
from aaeval.scenes import load_scene  # noqa: E402
from aaeval.groundtruth import groundtruth_phong  # noqa: E402
from aaeval.specular.render import render_shaded, specular_aliasing_map  # noqa: E402
from aaeval.specular.tables import cutoff_table, maximum  # noqa: E402
from specular_experiment import progress_bars  # noqa: E402

PLATE_METHODS = [
    ("none", {}),
    ("amanatides", {}),
    ("amanatides P=0.999", {"specular": "amanatides", "power": 0.999}),
    ("crow K=4", {"specular": "crow", "k": 4}),
    ("toksvig", {}),
    ("vlachos", {}),
    ("tokuyoshi", {}),
]


def options_of(label, extra):
    return extra or {"specular": label}


def fig_power_cutoff(out: Path) -> None:
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
    fig.tight_layout()
    fig.savefig(out / "fig2_power_cutoff.png", dpi=120)
    plt.close(fig)


def cosine_amplitudes(n: int, m: np.ndarray) -> np.ndarray:
    """Amplitude of cos(m x) in cos^n x (0 where m > n or parities differ)."""
    ok = (m <= n) & ((n - m) % 2 == 0)
    k = (n - m[ok]) // 2
    amp = np.zeros(len(m))
    amp[ok] = np.exp(gammaln(n + 1) - gammaln(k + 1) - gammaln(n - k + 1) - n * np.log(2.0))
    amp[ok & (m > 0)] *= 2
    return amp


def fig_clamp_ratio(out: Path) -> None:
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
    fig.tight_layout()
    fig.savefig(out / "fig3_clamp_ratio.png", dpi=120)
    plt.close(fig)


def plates(scene_path: str, name: str, out: Path, spp: int, frame: int, zoom) -> None:
    scene = load_scene(scene_path).at_frame(frame)
    truth, _, _ = groundtruth_phong(scene, spp=spp)
    images = [("Mitsuba Phong (truth)", truth)]
    for label, extra in PLATE_METHODS:
        images.append((label, render_shaded(scene, **options_of(label, extra))))
    cols = len(images)
    fig, axes = plt.subplots(3, cols, figsize=(2.1 * cols, 6.9), layout="constrained")
    (y0, y1), (x0, x1) = zoom
    for j, (label, image) in enumerate(images):
        axes[0, j].imshow(linear_to_srgb8(image))
        axes[0, j].set_title(label, fontsize=8)
        axes[1, j].imshow(linear_to_srgb8(image[y0:y1, x0:x1]), interpolation="nearest")
        error = (image - truth)[y0:y1, x0:x1].mean(axis=2)
        rmse = np.sqrt(np.mean((image - truth) ** 2))
        im = axes[2, j].imshow(error, cmap="RdBu_r", vmin=-0.3, vmax=0.3, interpolation="nearest")
        axes[2, j].set_title(f"zoom error; image RMSE {rmse:.4f}" if j else "zoom error (truth: 0)", fontsize=7)
    for ax in axes.ravel():
        ax.set_xticks([])
        ax.set_yticks([])
    axes[1, 0].set_ylabel(f"zoom rows {y0}-{y1}, cols {x0}-{x1}", fontsize=7)
    axes[2, 0].set_ylabel("signed error (mean of RGB)", fontsize=7)
    fig.colorbar(im, ax=axes[2, :], shrink=0.8, fraction=0.02)
    fig.suptitle(f"{name}, frame {frame}: Catmull renderer, one shade per visible piece per pixel, under each "
                 f"specular option; reference Mitsuba Phong, {spp} spp stratified, seed 0, box filter")
    fig.savefig(out / f"plates_{name}.png", dpi=110)
    plt.close(fig)


def fig_detection(scene_path: str, out: Path) -> None:
    scene = load_scene(scene_path)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.8))
    for ax, power in zip(axes[:2], (1.0, 0.999)):
        m = specular_aliasing_map(scene, power=power)
        im = ax.imshow(np.log2(np.maximum(m.rate, 1e-3)), cmap="magma", vmin=-4, vmax=8)
        ax.contour(m.flag, levels=[0.5], colors="c", linewidths=0.5)
        ax.set_title(f"log2 oversampling rate, power {power} (cyan: flagged)", fontsize=8)
        fig.colorbar(im, ax=ax, fraction=0.046)
    m = specular_aliasing_map(scene)
    im = axes[2].imshow(np.degrees(np.arccos(m.dot)), cmap="viridis")
    axes[2].set_title("largest normal turn in the pixel (degrees)", fontsize=8)
    fig.colorbar(im, ax=axes[2], fraction=0.046)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(out / "detection_cylinders.png", dpi=110)
    plt.close(fig)


def fig_flicker(scene_path: str, out: Path, spp: int, progress, rows=slice(170, 230), column=220) -> None:
    """Energy of one cross-section of the lower-right highlight (one pixel column) per frame."""
    scene = load_scene(scene_path)
    frames = list(range(scene.frames))
    truth = [groundtruth_phong(scene.at_frame(k), spp=spp)[1][rows, column].sum() for k in progress(frames, "truth")]
    fig, ax = plt.subplots(figsize=(6.8, 4.2))
    ax.plot(frames, truth, "k-", lw=2.5, label=f"Mitsuba Phong (truth, {spp} spp stratified, seed 0)")
    for label, extra in PLATE_METHODS:
        energy = []
        for k in progress(frames, label):
            _, spec = render_shaded(scene.at_frame(k), **options_of(label, extra), return_specular=True)
            energy.append(spec[rows, column].sum())
        ax.plot(frames, energy, marker=".", label=label)
    ax.set(xlabel="frame", ylabel="specular energy in the column",
           title=f"Cross-section of the lower-right highlight (column {column}) over the animation")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out / "highlight_flicker.png", dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp", type=int, default=1024)
    parser.add_argument("--out", default="reports/specular")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    progress = progress_bars(args.quiet)

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig_power_cutoff(out)
    fig_clamp_ratio(out)
    plates("configs/scenes/shaded/cylinders.toml", "cylinders", out, args.spp, 0, ((172, 220), (190, 238)))
    plates("configs/scenes/shaded/cones.toml", "cones", out, args.spp, 0, ((20, 68), (62, 110)))
    fig_detection("configs/scenes/shaded/cylinders.toml", out)
    fig_flicker("configs/scenes/shaded/cylinders.toml", out, args.spp, progress)
    if not args.quiet:
        print(f"figures written to {out}/")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
