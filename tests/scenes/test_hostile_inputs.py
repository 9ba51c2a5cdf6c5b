"""Hostile input files: every reader refuses non-regular and oversized files
before reading; a source file that is not SVG or not a font is one line naming it, exit 2;
resvg draws no file the SVG names; and resvg places viewBox-only SVGs as the importer does."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from aaeval.cli import main

from tests.helpers.cli_util import refused

SQUARE = """[image]
width = 8
height = 8
background = [1.0, 1.0, 1.0]

[[polygons]]
color = [0.0, 0.0, 0.0]
vertices = [[1.0, 1.0, 1.0], [5.0, 1.0, 1.0], [5.0, 5.0, 1.0], [1.0, 5.0, 1.0]]
"""

SVG_SCENE = """[image]
width = 8
height = 8
background = [1.0, 1.0, 1.0]

[svg]
file = "{file}"
scale = 1.0
tolerance = 0.0625
ignored = []

[[polygons]]
color = [0.0, 0.0, 0.0]
vertices = [[1.0, 1.0, 1.0], [5.0, 1.0, 1.0], [5.0, 5.0, 1.0], [1.0, 5.0, 1.0]]
"""

GOOD_SVG = '<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><rect x="1" y="1" width="4" height="4"/></svg>'


# --- the one bounded reader -------------------------------------------------------------

def test_reader_refuses_devices_folders_fifos_and_big_files(tmp_path, monkeypatch):
    from aaeval.readlimits import FileLimitError, read_bytes

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    for path, rule in [("/dev/zero", "character device"), (tmp_path, "folder"), (fifo, "FIFO")]:
        with pytest.raises(FileLimitError, match="not a regular file"):
            read_bytes(path, what="scene file")
    big = tmp_path / "big.toml"
    big.write_bytes(b"#" * 5000)
    with pytest.raises(FileLimitError, match="over the limit"):
        read_bytes(big, what="scene file", limit=4096)
    monkeypatch.setenv("AAEVAL_MAX_FILE_BYTES", "4K")
    with pytest.raises(FileLimitError, match="AAEVAL_MAX_FILE_BYTES"):
        read_bytes(big, what="scene file")
    with pytest.raises(FileLimitError):
        read_bytes(big, what="scene file", limit=10**9)
    monkeypatch.setenv("AAEVAL_MAX_FILE_BYTES", "banana")
    with pytest.raises(FileLimitError, match="AAEVAL_MAX_FILE_BYTES"):
        read_bytes(big, what="scene file")


def test_scene_from_dev_zero_or_a_fifo_is_refused_before_reading(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)  # reading it would block forever
    refused(["render", str(fifo), "-m", "point", "-o", "x.npy"], capsys, fifo, "FIFO")
    refused(["render", "/dev/zero", "-m", "point", "-o", "x.npy"], capsys, "/dev/zero")
    assert not (tmp_path / "x.npy").exists()


def test_oversized_scene_and_config_are_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("AAEVAL_MAX_FILE_BYTES", "1K")
    scene = tmp_path / "s.toml"
    scene.write_text(SQUARE + "#" * 2000 + "\n")
    refused(["render", str(scene), "-m", "point", "-o", "x.npy"], capsys, scene, "AAEVAL_MAX_FILE_BYTES")
    config = tmp_path / "e.toml"
    config.write_text("#" * 2000 + "\n")
    refused(["sweep", str(config), "--out", str(tmp_path / "out"), "--dry-run"], capsys, config)


# --- [svg].file under resvg ----------------------------------------------------------------

def svg_scene(tmp_path, file: str) -> Path:
    scene = tmp_path / "s.toml"
    scene.write_text(SVG_SCENE.format(file=file))
    return scene


@pytest.mark.parametrize("content", [
    b"",  # empty
    b"this is not xml",
    b"<svg xmlns='http://www.w3.org/2000/svg'><rect></svg>",  # broken XML
    b"\xff\xfe\x00garbage",  # not UTF-8
    b"<html><body/></html>",  # XML, not SVG
    # an entity bomb: a billion "a"s from a 500-byte file
    ("<?xml version='1.0'?><!DOCTYPE svg [<!ENTITY a0 'aaaaaaaaaa'>"
     + "".join(f"<!ENTITY a{i + 1} '{('&a%d;' % i) * 10}'>" for i in range(8))
     + "]><svg xmlns='http://www.w3.org/2000/svg'><title>&a8;</title></svg>").encode(),
])
def test_resvg_refuses_a_source_that_is_not_svg(tmp_path, capsys, monkeypatch, content):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.svg").write_bytes(content)
    refused(["render", str(svg_scene(tmp_path, "bad.svg")), "-m", "resvg", "-o", "x.npy"], capsys, "bad.svg")
    assert not (tmp_path / "x.npy").exists()


@pytest.mark.parametrize("target", ["/dev/zero", "fifo"])
def test_resvg_refuses_a_source_that_is_not_a_regular_file(tmp_path, capsys, monkeypatch, target):
    monkeypatch.chdir(tmp_path)
    if target == "fifo":
        os.mkfifo(tmp_path / "fifo")
    refused(["render", str(svg_scene(tmp_path, target)), "-m", "resvg", "-o", "x.npy"], capsys, target,
            "not a regular file")


def test_resvg_refuses_a_source_over_the_size_limit(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "big.svg").write_text(GOOD_SVG.replace("</svg>", "<!--" + "x" * 5000 + "--></svg>"))
    monkeypatch.setenv("AAEVAL_MAX_FILE_BYTES", "4K")
    refused(["render", str(svg_scene(tmp_path, "big.svg")), "-m", "resvg", "-o", "x.npy"], capsys, "big.svg",
            "over the limit")


def test_resvg_reads_and_embeds_no_other_file(tmp_path, capsys, monkeypatch):
    """A hand-edited scene's SVG naming a local raster (<image href>) or another file
    (<use href="other.svg#x">) is refused, saying why; resvg never reads the file."""
    from PIL import Image

    monkeypatch.chdir(tmp_path)
    Image.new("RGB", (8, 8), (255, 0, 0)).save(tmp_path / "secret.png")
    for element in ['<image href="secret.png" width="8" height="8"/>',
                    '<image xmlns:xlink="http://www.w3.org/1999/xlink" xlink:href="file:///etc/passwd" width="8" height="8"/>',
                    '<use href="other.svg#r"/>']:
        (tmp_path / "img.svg").write_text(GOOD_SVG.replace("</svg>", element + "</svg>"))
        err = refused(["render", str(svg_scene(tmp_path, "img.svg")), "-m", "resvg", "-o", "x.npy"], capsys,
                      "img.svg")
        assert "self-contained" in err
    assert not (tmp_path / "x.npy").exists()


def test_resvg_refuses_a_use_bomb_in_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    levels = ['<g id="l0"><rect width="1" height="1"/></g>']
    for n in range(1, 12):
        levels.append(f'<g id="l{n}">' + f'<use href="#l{n - 1}"/>' * 5 + "</g>")
    (tmp_path / "bomb.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8"><defs>'
                                       + "".join(levels) + '</defs><use href="#l11"/></svg>')
    refused(["render", str(svg_scene(tmp_path, "bomb.svg")), "-m", "resvg", "-o", "x.npy"], capsys, "bomb.svg")


def test_resvg_refuses_a_source_the_import_refuses_before_drawing_it(tmp_path, capsys, monkeypatch):
    """A scene whose source the importer refuses cannot be that source's import: resvg
    refuses it in the importer's words and draws nothing (an 801-point star crosses itself
    into 640,000 edges; the 100,000-point one the fuzz test met took resvg 17 s a render)."""
    import math

    monkeypatch.chdir(tmp_path)
    n, k = 801, 399
    points = " L".join(f"{4 + 3 * math.cos(2 * math.pi * k * i / n):.4f} {4 + 3 * math.sin(2 * math.pi * k * i / n):.4f}"
                       for i in range(n))
    (tmp_path / "star.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="8">'
                                       f'<path d="M{points} Z"/></svg>')
    err = refused(["render", str(svg_scene(tmp_path, "star.svg")), "-m", "resvg", "-o", "x.npy"], capsys, "star.svg",
                  "the import refuses the source", "crosses itself", written=[tmp_path / "x.npy"])
    assert "over the limit of" in err


def test_resvg_still_draws_internal_references(tmp_path, monkeypatch):
    from aaeval.renderers import render
    from aaeval.scenes import load_scene

    (tmp_path / "use.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" '
                                      'width="8" height="8"><defs><rect id="r" x="1" y="1" width="4" height="4"/></defs>'
                                      '<use xlink:href="#r"/></svg>')
    image = render(load_scene(svg_scene(tmp_path, "use.svg")), "resvg")
    assert abs((1 - image[..., 0]).sum() - 16) < 1e-9


# --- [text].font under freetype -----------------------------------------------------------

def text_scene(tmp_path, font: str) -> Path:
    scene = tmp_path / "t.toml"
    assert main(["import", "text", "ab", "--size", "12", "-o", str(scene)]) == 0
    lines = [f'font = "{font}"' if line.startswith("font =") else line for line in scene.read_text().splitlines()]
    scene.write_text("\n".join(lines) + "\n")
    return scene


@pytest.mark.parametrize("content", [b"", b"not a font at all", b"\x00\x01\x00\x00" + b"\x00" * 60])
def test_freetype_refuses_a_font_that_is_not_a_font(tmp_path, capsys, monkeypatch, content):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.ttf").write_bytes(content)
    refused(["render", str(text_scene(tmp_path, "bad.ttf")), "-m", "freetype", "-o", "x.npy"], capsys, "bad.ttf")
    assert not (tmp_path / "x.npy").exists()


def test_freetype_refuses_a_font_that_is_a_device_or_fifo(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.mkfifo(tmp_path / "fifo.ttf")
    for font in ["/dev/zero", "fifo.ttf"]:
        refused(["render", str(text_scene(tmp_path, font)), "-m", "freetype", "-o", "x.npy"], capsys, font,
                "not a regular file")


# --- resvg places a viewBox-only SVG once --------------------------------

@pytest.mark.parametrize("scale", [1, 2, 4])
def test_resvg_and_catmull_agree_on_viewbox_only_svgs(tmp_path, scale):
    """resvg blends in sRGB, so compare coverage (its sRGB darkness of black on white
    against the exact image's linear darkness); tiny-skia snaps edges to 1/4 px and rounds
    to 8 bits. Before the fix resvg drew the content ``scale`` times too large."""
    from aaeval.imageio import linear_to_srgb8
    from aaeval.importers.svg import import_svg
    from aaeval.renderers import render
    from aaeval.scenes import parse_scene

    svg = tmp_path / "v.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">'
                   '<rect x="1" y="1" width="4" height="4"/><circle cx="7.3" cy="6.6" r="1.9"/></svg>')
    result = import_svg(svg, scale=float(scale), file_ref="v.svg")
    scene = parse_scene(result.document, source=str(tmp_path / "v.toml"))
    assert (scene.width, scene.height) == (10 * scale, 10 * scale)
    coverage_resvg = 1 - linear_to_srgb8(render(scene, "resvg"))[..., 0] / 255.0
    coverage_exact = 1 - render(scene, "catmull")[..., 0]
    assert np.abs(coverage_resvg - coverage_exact).max() < 0.14
    ink = (16 + np.pi * 1.9**2) * scale**2
    assert abs(coverage_resvg.sum() - ink) < 0.02 * ink


# --- case 2: every method estimates memory and time from the scene ------------------------

IDENTICAL = "[[polygons]]\ncolor = [1, 0.5, 0]\nvertices = [[1.3, 1.2, 0], [14.7, 2.1, 0], [3.1, 14.9, 0]]\n"


@pytest.fixture(scope="module")
def identical_triangles(tmp_path_factory):
    """The hostile case at 2000 triangles (every pair overlapping): small enough to render
    here if a budget were missing, so the test fails instead of exhausting the machine."""
    from aaeval.scenes import load_scene

    path = tmp_path_factory.mktemp("identical") / "tri.toml"
    path.write_text("[image]\nwidth = 16\nheight = 16\nbackground = [0.0, 0.0, 0.0]\n\n" + IDENTICAL * 2000)
    return path, load_scene(path)


def polygon_methods():
    from aaeval.renderers.registry import METHODS

    return sorted(name for name, m in METHODS.items() if m.requires is None and name != "mitsuba")


@pytest.mark.parametrize("limit", ["memory", "seconds"])
def test_every_polygon_method_refuses_a_scene_over_the_budget(identical_triangles, monkeypatch, limit):
    from aaeval.renderers import MethodError, render

    path, scene = identical_triangles
    # 2000 identical triangles: 2e6 overlapping pairs, each costing every method's near-tie
    # pass about 200 bytes and a microsecond (measured)
    monkeypatch.setenv("AAEVAL_MAX_MEMORY" if limit == "memory" else "AAEVAL_MAX_SECONDS",
                       "100M" if limit == "memory" else "0.5")
    methods = polygon_methods()
    assert {"weiler-atherton", "abuffer", "catmull", "point"} <= set(methods)
    for name in methods:
        with pytest.raises(MethodError, match="AAEVAL_MAX_MEMORY" if limit == "memory" else "AAEVAL_MAX_SECONDS"):
            render(scene, name)


def test_budget_refusal_is_one_line_before_any_work(identical_triangles, capsys, monkeypatch, tmp_path):
    path, _ = identical_triangles
    monkeypatch.setenv("AAEVAL_MAX_MEMORY", "100M")
    for method in ["weiler-atherton", "abuffer"]:
        err = refused(["render", str(path), "-m", method, "-o", str(tmp_path / "x.npy")], capsys, path,
                      "overlapping polygon pairs")
        assert "GiB of memory" in err
    assert not (tmp_path / "x.npy").exists()
    # hidden-lines solves the scene with Weiler-Atherton too
    refused(["hidden-lines", str(path), "-o", str(tmp_path / "x.svg")], capsys, path, "GiB of memory")
    assert not (tmp_path / "x.svg").exists()


def test_scene_load_counts_match_brute_force():
    """Overlapping box pairs against shapely's STRtree, depth per pixel against a loop."""
    import shapely
    from shapely.geometry import box

    from aaeval.renderers.cost import scene_load
    from aaeval.scenes.generate import random_triangles

    for n, size, w in [(300, 6.0, 40), (3000, 30.0, 256)]:
        scene = random_triangles(n, w, w, size=size, seed=3)
        boxes = []
        for p in scene.polygons:
            if np.any(p.vertices[:, :2].min(axis=0) >= w) or np.any(p.vertices[:, :2].max(axis=0) <= 0):
                continue  # wholly outside the image
            lo = np.clip(p.vertices[:, :2].min(axis=0), 0, w)
            hi = np.clip(p.vertices[:, :2].max(axis=0), 0, w)
            boxes.append((lo, hi))
        geoms = [box(lo[0], lo[1], hi[0], hi[1]) for lo, hi in boxes]
        tree = shapely.STRtree(geoms)
        left, right = tree.query(geoms, predicate="intersects")
        exact_pairs = int((left < right).sum())
        load = scene_load(scene)
        if n <= 2048:
            assert load.pairs == exact_pairs
        else:  # sampled: within a fifth
            assert abs(load.pairs - exact_pairs) < 0.2 * exact_pairs
        depth = np.zeros((w, w))
        for lo, hi in boxes:
            x0, y0 = np.floor(lo).astype(int)
            x1, y1 = np.maximum(np.ceil(hi).astype(int), [x0 + 1, y0 + 1])
            depth[y0:y1, x0:x1] += 1
        assert load.depth_squares == (depth**2).sum() and load.fragments == depth.sum()
