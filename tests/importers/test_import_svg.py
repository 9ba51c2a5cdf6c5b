"""``aaeval import svg`` against an independent reference: for every fill and stroke of
the test SVGs (basic shapes, transforms, both fill rules, strokes, arcs and curves), the
imported region matches GEOS's region of svgelements' own finely sampled outline (fills
classified face by face by winding number; strokes as GEOS buffers) to the flattening
tolerance; ignored elements are listed by id; bad files are refused with one line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
import svgelements as se
from shapely.geometry import LineString, Point
from shapely.geometry import Polygon as ShapelyPolygon

from aaeval.cli import main
from aaeval.importers.flatten import arc_points, bezier_points, bezier_steps
from aaeval.importers.svg import import_svg
from aaeval.renderers import render
from aaeval.scenes import load_scene, parse_scene

DATA = Path(__file__).parents[1] / "data" / "svg"
ROOT = Path(__file__).parents[2]
FILES = ["shapes", "transforms", "fill_rules", "strokes", "arcs"]
FINE = 2049  # samples per curved segment for the reference outline

CAPS = {"butt": "flat", "round": "round", "square": "square"}
JOINS = {"miter": "mitre", "round": "round", "bevel": "bevel"}


def fine_subpaths(path):
    """svgelements' own points along every segment, densely: (points, closed) per subpath."""
    out, points = [], []
    for seg in path:
        if isinstance(seg, se.Move):
            if len(points) > 1:
                out.append((np.array(points), False))
            points = [(seg.end.x, seg.end.y)]
        elif isinstance(seg, se.Close):
            out.append((np.array(points), True))
            points = []
        else:
            n = 2 if isinstance(seg, se.Line) else FINE
            points.extend(np.asarray(seg.npoint(np.linspace(0, 1, n)))[1:].tolist())
    if len(points) > 1:
        out.append((np.array(points), False))
    return out


def winding(point, rings):
    x, y = point
    total = 0
    for ring in rings:
        a, b = ring, np.roll(ring, -1, axis=0)
        cross = (b[:, 0] - a[:, 0]) * (y - a[:, 1]) - (x - a[:, 0]) * (b[:, 1] - a[:, 1])
        up = (a[:, 1] <= y) & (b[:, 1] > y) & (cross > 0)
        down = (a[:, 1] > y) & (b[:, 1] <= y) & (cross < 0)
        total += int(up.sum()) - int(down.sum())
    return total


def fill_reference(subpaths, rule):
    rings = [p for p, _ in subpaths if len(p) >= 3]
    lines = shapely.unary_union([LineString(np.vstack([r, r[:1]])) for r in rings])
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
    keep = []
    for face in faces:
        w = winding(face.representative_point().coords[0], rings)
        if (w != 0) if rule == "nonzero" else (w % 2 == 1):
            keep.append(face)
    return shapely.unary_union(keep)


def stroke_reference(subpaths, width, cap, join, miter):
    parts = []
    for points, closed in subpaths:
        line = ShapelyPolygon(points).exterior if closed else LineString(points)
        parts.append(line.buffer(width / 2, quad_segs=64, cap_style=CAPS[cap], join_style=JOINS[join], mitre_limit=miter))
    return shapely.unary_union(parts)


def reference_layers(path):
    svg = se.SVG.parse(str(path), reify=True)
    layers = []
    for e in svg.elements():
        if not isinstance(e, se.Shape):
            continue
        subpaths = fine_subpaths(abs(se.Path(e)))
        if e.fill is not None and e.fill.value is not None:
            layers.append((e.id + " fill", fill_reference(subpaths, e.values.get("fill-rule", "nonzero"))))
        if e.stroke is not None and e.stroke.value is not None and e.implicit_stroke_width > 0:
            v = e.values
            layers.append((e.id + " stroke", stroke_reference(
                subpaths, e.implicit_stroke_width, v.get("stroke-linecap", "butt"),
                v.get("stroke-linejoin", "miter"), float(v.get("stroke-miterlimit", 4)))))
    return [(label, region) for label, region in layers if region.area > 0]  # a line fills nothing


def imported_layers(document):
    """The imported polygons grouped by layer (each layer on its own depth plane, first farthest)."""
    by_z = {}
    for p in document["polygons"]:
        z = p["vertices"][0][2]
        shape = ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h] for h in p.get("holes", [])])
        by_z.setdefault(z, []).append(shape)
    return [shapely.unary_union(by_z[z]) for z in sorted(by_z, reverse=True)]


@pytest.mark.slow
@pytest.mark.parametrize("tol", [1 / 16, 1 / 4])
@pytest.mark.parametrize("name", FILES)
def test_imported_regions_match_geos_reference_to_tolerance(name, tol):
    result = import_svg(DATA / f"{name}.svg", tolerance=tol)
    assert result.ignored == []
    got = imported_layers(result.document)
    expected = reference_layers(DATA / f"{name}.svg")
    assert len(got) == len(expected)
    for g, (label, e) in zip(got, expected):
        perimeter = e.boundary.length
        # every boundary point within tol (Hausdorff distance of the outlines) ...
        gap = shapely.hausdorff_distance(g.boundary, e.boundary, densify=0.02)
        assert gap <= tol * 1.02 + 1e-4, (label, gap)
        # ... so area and symmetric difference stay within tol per unit of outline
        assert abs(g.area - e.area) <= tol * perimeter, (label, g.area, e.area)
        assert g.symmetric_difference(e).area <= tol * perimeter, label


def test_flattening_is_adaptive_not_fine():
    """Vertices where the curve needs them: a circle of radius r gets about
    pi / acos(1 - tol / r) of them, and a straight 'curve' just one step."""
    for r, tol in [(8.0, 1 / 16), (40.0, 1 / 16), (8.0, 1 / 4)]:
        n = len(arc_points((0, 0), r, r, 0.0, 0.0, 2 * np.pi, tol))
        assert n == int(np.ceil(np.pi / np.arccos(1 - tol / r)))
        # and the chords' midpoints really are within tol of the circle
        assert r * (1 - np.cos(np.pi / n)) <= tol
    assert bezier_steps(np.array([[0, 0], [1, 1], [2, 2], [3, 3]], float), 1 / 16) == 1
    cubic = np.array([[0, 0], [10, 30], [30, -20], [40, 10]], float)
    pts = np.vstack([cubic[:1], bezier_points(cubic, 1 / 16)])
    t = np.linspace(0, 1, 20001)
    curve = ((1 - t) ** 3)[:, None] * cubic[0] + (3 * t * (1 - t) ** 2)[:, None] * cubic[1] \
        + (3 * t**2 * (1 - t))[:, None] * cubic[2] + (t**3)[:, None] * cubic[3]
    assert LineString(pts).hausdorff_distance(LineString(curve)) <= 1 / 16
    assert len(pts) < 60


def test_a_quadratic_gets_wangs_step_count_to_the_bit():
    # the bound computed here on arrays, as for every other degree; quadratics take plain
    # floats: the same count, also where the square root lands on a whole number
    rng = np.random.default_rng(11)
    curves = rng.normal(size=(3000, 3, 2)) * np.exp(rng.uniform(-12, 12, (3000, 1, 1)))
    exact = np.array([[0, 0], [-2, 0], [0, 0]], float)  # |P0 - 2 P1 + P2| = 4: the bound is 4 steps exactly
    assert bezier_steps(exact, 1 / 16) == 4
    for control in [*curves, exact]:
        second = control[2:] - 2.0 * control[1:-1] + control[:-2]
        m = float(np.hypot(second[:, 0], second[:, 1]).max())
        wang = int(min(1 << 16, max(1, np.ceil(np.sqrt(2 * m / (8.0 / 16))))))
        assert bezier_steps(control, 1 / 16) == wang
    with pytest.raises(ValueError, match="not a finite number"):
        bezier_steps(np.array([[0, 0], [np.inf, 1], [2, 2]], float), 1 / 16)


def test_fill_rules_give_holes_where_they_should():
    result = import_svg(DATA / "fill_rules.svg")
    scene = parse_scene(result.document)
    # squares of opposite winding under nonzero: a hole; three nested squares under
    # even-odd: a hole with an island in it; same winding: none. (The even-odd star is
    # five points that touch at the pentagon's corners: no ring encloses the pentagon.)
    holes = [len(h.rings) - 1 for h in scene.holed]
    assert holes == [1, 1]
    assert len(scene.polygons) - sum(h.count for h in scene.holed) == 1 + 5 + 1 + 1  # stars, same winding, island


def test_every_ignored_element_is_listed_by_id(tmp_path):
    svg = tmp_path / "mixed.svg"
    svg.write_text("""<svg xmlns="http://www.w3.org/2000/svg" width="20" height="20">
  <defs><linearGradient id="g"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient>
        <clipPath id="c"><rect width="5" height="5"/></clipPath></defs>
  <rect id="kept" x="1" y="1" width="5" height="5" fill="blue"/>
  <rect id="gradient" x="1" y="8" width="5" height="5" fill="url(#g)"/>
  <rect id="clipped" x="8" y="1" width="5" height="5" fill="red" clip-path="url(#elsewhere)"/>
  <rect id="faint" x="8" y="8" width="5" height="5" fill="red" opacity="0.5"/>
  <text id="words" x="1" y="19">hi</text>
  <rect x="14" y="14" width="5" height="5" fill="red" filter="url(#f)"/>
</svg>""")
    result = import_svg(svg)
    listed = "\n".join(result.ignored)
    for expected in ["#gradient: fill url(#g)", "#clipped: clip-path url(#elsewhere) is not a clipPath", "#faint: opacity 0.5",
                     "#words: text element", "rect[4]: filter"]:
        assert expected in listed, (expected, listed)
    assert parse_scene(result.document).extensions["svg"].ignored == tuple(result.ignored)


def test_one_subprocess_run_exits_2_with_one_line(tmp_path):
    (tmp_path / "bad.svg").write_text("<svg")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-m", "aaeval", "import", "svg", "bad.svg", "-o", "out.toml"],
                          capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1 and "bad.svg" in done.stderr


@pytest.mark.parametrize("content", ["<svg", "not xml at all", '<svg xmlns="http://www.w3.org/2000/svg" width="0" height="5"/>'])
def test_bad_svg_is_refused_with_one_line(tmp_path, monkeypatch, capsys, content):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.svg").write_text(content)
    (tmp_path / "out.toml").write_text("kept")
    assert main(["import", "svg", "bad.svg", "-o", "out.toml"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "bad.svg" in err
    assert (tmp_path / "out.toml").read_text() == "kept"


def test_cli_writes_a_scene_every_method_reads(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["import", "svg", str(DATA / "strokes.svg"), "-o", "s.toml", "--frames", "3", "--translate", "0.125", "0"]) == 0
    scene = load_scene(tmp_path / "s.toml")
    assert scene.frames == 3 and scene.extensions["svg"].file.endswith("strokes.svg")
    exact = render(scene.at_frame(1), "catmull")
    np.testing.assert_allclose(render(scene.at_frame(1), "weiler-atherton"), exact, atol=1e-9)
    assert main(["import", "svg", str(DATA / "shapes.svg"), "-o", "t.toml", "--strict"]) == 0
    assert main(["import", "svg", str(DATA / "shapes.svg").replace("shapes", "missing"), "-o", "t.toml"]) == 2


def test_resvg_draws_the_source_in_place_at_every_frame(tmp_path):
    """resvg blends in sRGB: its sRGB-encoded darkness is the coverage of black on white,
    which the exact image gives in linear light; so compare coverage, frame by frame."""
    from aaeval.imageio import linear_to_srgb8

    svg = tmp_path / "r.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="12" height="9">'
                   '<rect x="2.25" y="1.5" width="4.5" height="3.75"/>'
                   '<circle cx="9.2" cy="5.1" r="2.0"/></svg>')
    result = import_svg(svg, frames=3, translate=(0.375, 0.25), file_ref="r.svg")
    scene = parse_scene(result.document, source=str(tmp_path / "r.toml"))
    for k in range(3):
        coverage_resvg = 1 - linear_to_srgb8(render(scene, "resvg", frame=k))[..., 0] / 255.0
        coverage_exact = 1 - render(scene, "catmull", frame=k)[..., 0]
        # resvg (tiny-skia) supersamples 4x per axis: an edge snaps by up to 1/8 px, so a
        # pixel on it is off by up to 1/8; 8-bit output; its own flattening of the circle
        assert np.abs(coverage_resvg - coverage_exact).max() < 0.14
        # in place: the ink's centre is where the exact one is, up to the snapping
        rows, cols = np.mgrid[: scene.height, : scene.width]
        for grid in (rows, cols):
            centre = [(c * grid).sum() / c.sum() for c in (coverage_resvg, coverage_exact)]
            assert abs(centre[0] - centre[1]) <= 0.13  # 1/8 px snapping at most


def test_resvg_refuses_scenes_that_ignored_something(tmp_path):
    svg = tmp_path / "o.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><rect id="half" width="2" height="2" opacity="0.5"/></svg>')
    scene = parse_scene(import_svg(svg, file_ref="o.svg").document, source=str(tmp_path / "o.toml"))
    with pytest.raises(ValueError, match="#half: opacity"):
        render(scene, "resvg")


@pytest.mark.parametrize("name", ["transforms", "fill_rules", "arcs"])
def test_layers_stand_where_svgelements_puts_the_shapes(name):
    """Bounds of each imported fill against svgelements' own transformed bounding box
    (computed from the element and its transform, not from the reified points)."""
    svg = se.SVG.parse(str(DATA / f"{name}.svg"))
    boxes = [e.bbox() for e in svg.elements() if isinstance(e, se.Shape) and e.fill is not None and e.fill.value is not None]
    fills = imported_layers(import_svg(DATA / f"{name}.svg").document)  # these files have fills only
    assert len(fills) == len(boxes)
    for box, g in zip(boxes, fills):
        np.testing.assert_allclose(g.bounds, box, atol=1 / 16 + 1e-5)


def test_use_is_placed_and_nested_svg_gets_its_viewport_and_clip(tmp_path):
    svg = tmp_path / "use.svg"
    body = ('<defs><path id="tri" d="M 0 0 L 6 0 L 3 5 Z"/></defs>'
            '<use href="#tri" x="2" y="3" fill="red"/><use href="#tri" transform="translate(15 8) scale(2)" fill="blue"/>')
    svg.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="30" height="20">{body}</svg>')
    layers = imported_layers(import_svg(svg).document)
    np.testing.assert_allclose([g.bounds for g in layers], [(2, 3, 8, 8), (15, 8, 27, 18)], atol=1e-6)
    # the viewBox maps 20 user units onto 10 px at x = 10; the 40-unit square is clipped to it
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="30" height="20">'
                   '<svg x="10" width="10" height="10" viewBox="0 0 20 20"><rect x="5" y="-5" width="40" height="40"/>'
                   '</svg></svg>')
    (square,) = imported_layers(import_svg(svg).document)
    np.testing.assert_allclose(square.bounds, (12.5, 0, 20, 10), atol=1e-12)
    assert square.area == pytest.approx(7.5 * 10, abs=1e-9)
