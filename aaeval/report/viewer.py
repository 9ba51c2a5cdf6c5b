"""The report's interactive comparison viewer: the data it shows and the page snippets.

For every group, ``viewer/<slug>.js`` holds each scene's frames for the ground truth and
every method (linear RGB), each method's signed error (mean over RGB, computed here in
float64 so that errors far below float16's step near 1 keep their value) and its FLIP
map (measured by the sweep, ``flip/<key>.npy``), as zlib-compressed float16 arrays (the FLIP map as bytes, 1/255 steps) in base64 inside
an ``AAV.add(...)`` call. The page
loads these files with plain ``<script src>`` tags, which work from ``file://``; the
viewer itself (``viewer.js`` beside this module, with the colour maps filled in at build
time) is written inline into the page. Nothing is fetched from the network.

The raw float64 images stay in the sweep's ``images/`` and ``references/`` folders; the
page needs only ``index.html``, ``figures/`` and ``viewer/``.
"""

from __future__ import annotations

import base64
import json
import zlib
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.sweeps.summaries import changing_row
from aaeval.fileio import atomic_write
from aaeval.report.style import Styles

__all__ = ["viewer_payload", "write_viewer_data", "viewer_div", "viewer_script", "GROUP_BUDGET",
           "scene_series"]

# Above this many bytes of viewer data a group keeps its first scenes only (the page
# must stay small enough to open from disk).
GROUP_BUDGET = 6_000_000


def _blob(array: np.ndarray) -> str:
    half = np.ascontiguousarray(np.asarray(array, dtype="<f2"))
    return base64.b64encode(zlib.compress(half.tobytes(), 6)).decode("ascii")


def _blob8(array: np.ndarray) -> str:
    """Values in [0, 1] as bytes (steps of 1/255: the viewer's colour maps have 256 entries)."""
    codes = np.round(np.clip(array, 0.0, 1.0) * 255).astype(np.uint8)
    return base64.b64encode(zlib.compress(codes.tobytes(), 6)).decode("ascii")


def scene_series(ok: pd.DataFrame, store, scene: str, styles: Styles):
    """(ground-truth frames, [(row of the spec, frames)], frame numbers) of one scene:
    arrays (F, H, W, 3), specs in legend order, frames where every spec has an image."""
    rows = ok[ok["scene"] == scene]
    frames = sorted(rows["frame"].unique())
    specs = []
    for _, r in rows.groupby("spec", sort=False):
        if set(r["frame"]) >= set(frames):
            specs.append(r.sort_values("frame").drop_duplicates("frame"))
    specs.sort(key=lambda r: styles.order(r["method"].iloc[0], r["options"].iloc[0]))
    if not specs:
        return None, [], frames
    first = specs[0]
    refs = [store.load_reference(store.read_cell(k)["reference_key"]) for k in first["key"]]
    if any(r is None for r in refs):
        return None, [], frames
    series = []
    for r in specs:
        imgs = [store.load_image(k) for k in r["key"]]
        if all(i is not None for i in imgs):
            series.append((r, np.stack(imgs)))
    return np.stack(refs), series, frames


def viewer_payload(ok: pd.DataFrame, store, styles: Styles, *, budget: int = GROUP_BUDGET) -> tuple[dict, list]:
    """The viewer data of one group's finished cells, and the scenes left out for size."""
    scenes, left_out, size = [], [], 0
    for scene in dict.fromkeys(ok["scene"]):
        reference, series, frames = scene_series(ok, store, scene, styles)
        if reference is None or not series:
            continue
        panels = [{"label": f"ground truth: {ok[ok['scene'] == scene]['reference'].iloc[0]}", "method": "ground truth",
                   "colour": "#555555", "img": _blob(reference), "error": None, "flip": None}]
        for rows, imgs in series:
            st = styles.spec(rows["method"].iloc[0], rows["options"].iloc[0])
            signed = (imgs - reference).mean(axis=3)
            flips = [store.load_flip(k) for k in rows["key"]]  # measured by the sweep (none: no FLIP view)
            panels.append({"label": rows["label"].iloc[0], "method": rows["method"].iloc[0],
                           "colour": "#%02x%02x%02x" % tuple(int(round(255 * c)) for c in st.colour),
                           "img": _blob(imgs), "error": _blob(signed),
                           "flip": _blob8(np.stack(flips)) if all(f is not None for f in flips) else None})
        entry = {"name": scene, "width": int(reference.shape[2]), "height": int(reference.shape[1]),
                 "frames": len(frames), "frame_numbers": [int(f) for f in frames],
                 "row": changing_row(reference), "panels": panels}
        cost = sum(len(p["img"]) + len(p["error"] or "") + len(p["flip"] or "") for p in panels)
        if scenes and size + cost > budget:
            left_out.append(scene)
            continue
        size += cost
        scenes.append(entry)
    return {"scenes": scenes}, left_out


def write_viewer_data(directory: Path, slug: str, payload: dict) -> Path:
    path = Path(directory) / f"{slug}.js"
    text = f"AAV.add({json.dumps(slug)}, {json.dumps(payload, separators=(',', ':'))});\n"
    atomic_write(path, lambda tmp: Path(tmp).write_text(text))
    return path


def viewer_div(slug: str) -> str:
    return f"<div class='aav' data-group='{slug}'>loading the viewer…</div>"


def _lut(name: str) -> list[list[int]]:
    from matplotlib import colormaps

    rgba = colormaps[name](np.linspace(0.0, 1.0, 256))
    return np.round(rgba[:, :3] * 255).astype(int).tolist()


def viewer_script() -> str:
    """viewer.js with the colour maps (matplotlib's magma and RdBu_r, as numbers) filled in."""
    source = (Path(__file__).with_name("viewer.js")).read_text()
    luts = json.dumps({"magma": _lut("magma"), "rdbu": _lut("RdBu_r")}, separators=(",", ":"))
    return source.replace("/*LUTS*/ {}", luts)


VIEWER_CSS = """
.aav{border:1px solid #ccc;padding:.5em;margin:1em 0;outline:none} .aav:focus{border-color:#36c}
.aav-bar{display:flex;flex-wrap:wrap;gap:.4em;align-items:center;font-size:12px}
.aav-stage{display:flex;flex-wrap:wrap;gap:6px;margin-top:.4em}
.aav-panel{display:inline-block} .aav-panel canvas{display:block;background:#777;cursor:crosshair;image-rendering:pixelated}
.aav-cap{font-size:11px;padding-left:4px;max-width:560px;white-space:normal;overflow-wrap:anywhere}
.aav-panel canvas:focus{outline:2px solid #36c}
.aav-info{font-size:10px;color:#555} .aav-readout{font-family:monospace;font-size:11px;margin-top:.3em;min-height:1.2em}
.aav-help{font-size:11px;color:#666;margin-top:.3em}
"""
