"""Specular study on the animated cylinders: what is not a sweep.

The per-method numbers (highlight RMSE, highlight energy bias, highlight flicker, energy
flicker, image metrics, render times) are a sweep config measured by the same engine as
every other experiment::

    aaeval sweep configs/sweeps/specular.toml --out reports/specular-sweep
    aaeval report reports/specular-sweep

This script keeps the three analyses a sweep cannot express, each against the Mitsuba
Phong ground truth (cached on disk). Written to ``reports/specular/experiment.json`` and
``.md``:

- detection precision/recall of Amanatides' test (conservative and aggressive) against
  pixels where the unclamped image's error exceeds a tolerance,
- crow everywhere (region=all) against the truth for growing K: the convergence check,
- cross-section ("profile") flicker of the specular term in two hand-picked regions of the
  cylinders scene, each holding one highlight line, per method.

Usage: ``PYTHONPATH=. python scripts/specular_experiment.py [--frames N] [--spp S] [--quiet]``
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval.sweeps.typed_json import dumps
from aaeval.imageio import atomic_write
from aaeval.metrics import rmse
from aaeval.metrics.masks import HIGHLIGHT_THRESHOLD
from aaeval.metrics.specular import detection_precision_recall, highlight_mask, highlight_profile_flicker
from aaeval.renderers import resolve
from aaeval.scenes import load_scene
from aaeval.groundtruth import groundtruth_phong
from aaeval.specular.render import render_shaded, specular_aliasing_map

registries.load()  # a program fills the registries once, before it renders

SCENE = "configs/scenes/shaded/cylinders.toml"
# the methods whose cross-sections are compared (the sweep config has the full list)
METHODS = [
    "catmull:specular=none",
    "catmull:specular=amanatides",
    "catmull:specular=crow,k=4",
    "catmull:specular=toksvig",
    "catmull:specular=vlachos",
    "catmull:specular=tokuyoshi",
]
MASK_THRESHOLD = HIGHLIGHT_THRESHOLD  # the same highlight as the sweep's highlight metrics
# regions holding one highlight line each (cylinders scene): (rows, cols); the measure
# finds each line's direction and cuts it across
PROFILE_REGIONS = {
    "central": (slice(60, 160), slice(80, 180)),  # near-vertical line
    "lower right": (slice(170, 230), slice(195, 245)),  # near-horizontal line
}
DETECTION_TOLERANCE = 0.02


def progress_bars(quiet: bool):
    """``progress(iterable, label)``: a tqdm bar, or the bare iterable when quiet."""

    def progress(iterable, label):
        if quiet:
            return iterable
        from tqdm import tqdm

        return tqdm(iterable, desc=label, leave=False)

    return progress


def groundtruth_frames(scene, frames, spp, progress):
    rgb, spec = [], []
    for k in progress(range(frames), "ground truth"):
        image, specular, _ = groundtruth_phong(scene.at_frame(k), spp=spp)
        rgb.append(image)
        spec.append(specular)
    return np.array(rgb), np.array(spec)


def method_frames(scene, spec, frames, progress):
    """RGB and specular-only frames of one method (the specular term alone is not a sweep output)."""
    _, options = resolve(spec)
    rgb, specular = [], []
    for k in progress(range(frames), spec.split(":", 1)[1]):
        image, spec_image = render_shaded(scene.at_frame(k), **options, return_specular=True)
        rgb.append(image)
        specular.append(spec_image)
    return np.array(rgb), np.array(specular)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=SCENE)
    parser.add_argument("--frames", type=int, default=None, help="frames to use (default: all)")
    parser.add_argument("--spp", type=int, default=1024, help="ground-truth samples per pixel")
    parser.add_argument("--crow-k", default="1,2,4,8,16", help="K values of the crow-everywhere convergence check")
    parser.add_argument("--out", default="reports/specular")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    progress = progress_bars(args.quiet)

    scene = load_scene(args.scene)
    frames = min(args.frames or scene.frames, scene.frames)
    true_rgb, true_spec = groundtruth_frames(scene, frames, args.spp, progress)
    mask = highlight_mask(true_spec, threshold=MASK_THRESHOLD)

    regions = {}
    for name, (rows_, cols_) in PROFILE_REGIONS.items():
        region = np.zeros(true_spec.shape[1:], bool)
        region[rows_, cols_] = True
        regions[name] = region & mask.any(axis=0)

    rows = []
    plain_rgb = None
    for spec in METHODS:
        rgb, specular = method_frames(scene, spec, frames, progress)
        rows.append({
            "method": spec,
            **{f"profile_flicker_{name}": highlight_profile_flicker(true_spec, specular, mask=region)
               for name, region in regions.items()},
        })
        if spec.endswith("=none"):
            plain_rgb = rgb

    detection = []
    for power in (1.0, 0.999, 0.99):
        p, r, fraction = [], [], []
        for k in range(frames):
            flags = specular_aliasing_map(scene.at_frame(k), power=power).flag
            fraction.append(flags.mean())
            precision, recall = detection_precision_recall(
                true_rgb[k], plain_rgb[k], flagged=flags, tolerance=DETECTION_TOLERANCE
            )
            p.append(precision)
            r.append(recall)
        detection.append({"power": power, "precision": float(np.nanmean(p)), "recall": float(np.nanmean(r)),
                          "flagged_fraction": float(np.mean(fraction))})

    convergence = []
    for K in [int(v) for v in args.crow_k.split(",")]:
        start = time.perf_counter()
        image = render_shaded(scene.at_frame(0), specular="crow", k=K, region="all")
        convergence.append({"k": K, "rmse": rmse(true_rgb[0], image), "seconds": time.perf_counter() - start})

    report = {"scene": args.scene, "frames": frames, "spp": args.spp, "mask_threshold": MASK_THRESHOLD,
              "mask_pixels_per_frame": float(mask.sum() / frames), "methods": rows,
              "detection": detection, "crow_everywhere": convergence}
    text = format_report(report)
    print(text)
    out = Path(args.out)
    atomic_write(out / "experiment.json", lambda tmp: Path(tmp).write_text(dumps(report, indent=2)))
    atomic_write(out / "experiment.md", lambda tmp: Path(tmp).write_text(text))
    return 0


def format_report(report) -> str:
    lines = [
        f"Scene {report['scene']}, {report['frames']} frames, ground truth Mitsuba Phong "
        f"{report['spp']} spp; highlight = truth specular > {report['mask_threshold']} "
        f"({report['mask_pixels_per_frame']:.0f} px/frame). Per-method highlight error and flicker: "
        "the sweep configs/sweeps/specular.toml.",
        "",
        "| method | x-section flicker central | x-section flicker lower right |",
        "|---|---|---|",
    ]
    for r in report["methods"]:
        lines.append(f"| {r['method'].split(':', 1)[1]} | {r['profile_flicker_central']:.4f} "
                     f"| {r['profile_flicker_lower right']:.4f} |")
    lines += ["", "| detection power | precision | recall | flagged fraction of pixels |", "|---|---|---|---|"]
    for d in report["detection"]:
        lines.append(f"| {d['power']} | {d['precision']:.3f} | {d['recall']:.3f} | {d['flagged_fraction']:.4f} |")
    lines += ["", "| crow everywhere K | RMSE vs truth (frame 0) | s |", "|---|---|---|"]
    for c in report["crow_everywhere"]:
        lines.append(f"| {c['k']} | {c['rmse']:.6f} | {c['seconds']:.2f} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    raise SystemExit(main())
