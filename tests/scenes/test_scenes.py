"""The shipped scenes (configs/scenes) and the scene generators.

Rendered images are checked against an oracle built another way: exact polygon
booleans in GEOS (through shapely, ``tests/helpers/oracle.py``), intersected with every pixel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
import shapely.affinity

from aaeval.metrics.temporal import intensity_sum
from aaeval.renderers import render
from aaeval.catmull import visible_fragments
from aaeval.scenes import Scene, SceneError, load_scene, parse_scene
from aaeval.scenes.generate import (
    fan,
    picket_fence,
    random_polygons,
    random_triangles,
    slivers,
)
from aaeval.scenes.write import scene_to_dict, write_scene
from tests.helpers.oracle import oracle_image

SCENES_DIR = Path(__file__).resolve().parents[2] / "configs" / "scenes"
SHIPPED = sorted(SCENES_DIR.glob("*.toml"))
KHAN = ["rectangles", "triangles", "monochrome", "concave"]


def shipped(name: str) -> Scene:
    return load_scene(SCENES_DIR / f"{name}.toml")


# --- helpers ----------------------------------------------------------------------


def pixel_boxes(scene: Scene) -> np.ndarray:
    rows, cols = np.mgrid[0 : scene.height, 0 : scene.width]
    return shapely.box(cols.ravel(), rows.ravel(), cols.ravel() + 1, rows.ravel() + 1)


def area_per_pixel(scene: Scene, geometry) -> np.ndarray:
    """(H, W) area of ``geometry`` inside each pixel square."""
    return shapely.area(shapely.intersection(geometry, pixel_boxes(scene))).reshape(scene.height, scene.width)


def outline(polygon) -> shapely.Polygon:
    return shapely.Polygon(polygon.xy)


def catmull(scene: Scene, frame: int | None = None) -> np.ndarray:
    return render(scene, "catmull", frame=frame)


# --- every shipped scene ------------------------------------------------------------


def test_scenes_are_shipped():
    names = {p.stem for p in SHIPPED}
    expected = {"catmull_fig1", "picket_fence", "interpenetrating", "fan"}
    expected |= {f"khan_{k}_{v}" for k in KHAN for v in "ab"}
    assert expected <= names


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_scene_renders_with_catmull(path):
    scene = load_scene(path)
    assert not scene.extensions, "shipped scenes are written in the core keys only"
    colors = np.vstack([scene.background] + [p.color for p in scene.polygons])
    lo, hi = colors.min(axis=0), colors.max(axis=0)
    for k in range(scene.frames):
        image = catmull(scene, frame=k)
        assert image.shape == (scene.height, scene.width, 3)
        assert np.isfinite(image).all()
        # a box-filtered pixel is a convex combination of the scene's colours
        assert (image >= lo - 1e-12).all() and (image <= hi + 1e-12).all()


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_scene_has_a_comment_header(path):
    first = path.read_text().splitlines()[0]
    assert first.startswith("# ") and len(first) > 20


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_scene_matches_exact_geometry(path):
    scene = load_scene(path)
    for k in sorted({0, scene.frames // 2, scene.frames - 1}):
        at_k = scene.at_frame(k)
        np.testing.assert_allclose(catmull(at_k), oracle_image(at_k), rtol=0, atol=1e-10)


# --- Catmull's figure 1 -------------------------------------------------------------


def test_catmull_fig1_pixel_is_quarter_green_quarter_black_half_blue_no_red():
    scene = shipped("catmull_fig1")
    image = catmull(scene)
    np.testing.assert_allclose(image[1, 1], [0.0, 0.25, 0.5], rtol=0, atol=1e-12)
    assert np.abs(image[..., 0]).max() <= 1e-12, "red shows through somewhere"
    others = np.ones((3, 3), bool)
    others[1, 1] = False
    assert (image[others] == scene.background).all()


def test_catmull_fig1_pixel_fragments_by_colour():
    scene = shipped("catmull_fig1")
    frags = visible_fragments(scene)
    at = frags.pixel == 1 * scene.width + 1
    by_colour = {"black": 0.0, "red": 0.0, "green": 0.0, "blue": 0.0}
    names = {-1: "black"} | {p.index: ("red", "green", "blue")[int(np.argmax(p.color))] for p in scene.polygons}
    for polygon, area in zip(frags.polygon[at], frags.area[at]):
        by_colour[names[int(polygon)]] += area
    assert by_colour == pytest.approx({"black": 0.25, "red": 0.0, "green": 0.25, "blue": 0.5}, abs=1e-12)


def test_catmull_fig1_red_is_hidden_only_by_green_and_blue_together():
    # what makes the pixel hard: neither polygon alone hides the red one
    polygons = shipped("catmull_fig1").polygons
    red, green, blue = (outline(p) for p in polygons)
    assert red.difference(green).area > 0.01
    assert red.difference(blue).area > 0.01
    assert red.difference(green.union(blue)).area == 0.0
    assert max(p.vertices[:, 2].max() for p in polygons[1:]) < polygons[0].vertices[:, 2].min(), "red is behind"


# --- Khan's figures in both depth orders ---------------------------------------------


@pytest.mark.parametrize("name", KHAN)
def test_khan_depth_orders_differ_exactly_in_the_overlap(name):
    a, b = shipped(f"khan_{name}_a"), shipped(f"khan_{name}_b")
    assert [p.xy.tolist() for p in a.polygons] == [p.xy.tolist() for p in b.polygons]

    def front_colour(scene):
        return min(scene.polygons, key=lambda p: p.vertices[0, 2]).color

    assert not np.array_equal(front_colour(a), front_colour(b)), "the two files must swap the depth order"
    overlap = outline(a.polygons[0]).intersection(outline(a.polygons[1]))
    assert overlap.area > 1.0
    in_overlap = area_per_pixel(a, overlap)

    difference = catmull(a) - catmull(b)
    expected = in_overlap[..., None] * (front_colour(a) - front_colour(b))
    np.testing.assert_allclose(difference, expected, rtol=0, atol=1e-12)
    outside = in_overlap == 0.0
    assert outside.any() and (difference[outside] == 0.0).all()
    assert (np.abs(difference[in_overlap > 1e-6]).max(axis=-1) > 0).all()


# --- picket fence -------------------------------------------------------------------


def point_samples(scene: Scene) -> np.ndarray:
    """(H, W) mask of pixel centres inside the fence: a one-sample-per-pixel image."""
    rows, cols = np.mgrid[0 : scene.height, 0 : scene.width]
    fence = shapely.union_all([outline(p) for p in scene.polygons])
    return shapely.contains_xy(fence, cols + 0.5, rows + 0.5)


@pytest.mark.parametrize("name", ["picket_fence", "picket_fence_moire", "picket_fence_moire_21"])
def test_picket_fence_catmull_sum_is_constant(name):
    scene = shipped(name)
    assert scene.frames >= 8 and 0 < scene.translate[0] < 1
    assert max(np.ptp(p.xy[:, 0]) for p in scene.polygons) < 1.0, "bars must be thinner than a pixel"
    sums = np.array([intensity_sum(catmull(scene, frame=k)) for k in range(scene.frames)])
    assert np.ptp(sums) <= 1e-12 * sums.mean()
    bar_area = sum(outline(p).area for p in scene.polygons)
    assert sums.mean() == pytest.approx(3.0 * bar_area, rel=1e-12)


def test_picket_fence_point_sampled_sum_swings_from_black_to_white():
    scene = shipped("picket_fence")
    point = np.array([3.0 * point_samples(scene.at_frame(k)).sum() for k in range(scene.frames)])
    bar_pixels = len(scene.polygons) * (scene.height - 2)
    assert point.min() == 0.0 and point.max() == 3.0 * bar_pixels


def test_picket_fence_moire_point_samples_crawl_while_their_sum_stays():
    scene = shipped("picket_fence_moire")
    masks = [point_samples(scene.at_frame(k)) for k in range(scene.frames)]
    sums = [m.sum() for m in masks]
    assert max(sums) - min(sums) <= scene.height - 2  # at most one column's worth apart
    assert len({m.tobytes() for m in masks}) >= scene.frames // 2, "the aliased pattern moves"


def test_the_20_bar_moire_fence_is_invariant_for_point_sampling_and_21_bars_are_not():
    # 20 bars of period 1.3 px are two whole periods of the 13/10 beat with the pixel grid:
    # whatever the translation, the point samples cover the same number of bars. One bar
    # more and the count depends on where the fence stands (the 21-bar file's reason to be).
    def spread(name):
        scene = shipped(name)
        counts = []
        for shift in np.linspace(0.0, 1.3, 27, endpoint=False):
            moved = [shapely.affinity.translate(outline(p), shift) for p in scene.polygons]
            counts.append(sum(shapely.contains_xy(m, np.arange(scene.width) + 0.5, 1.5).sum() for m in moved))
        return np.ptp(counts)

    assert spread("picket_fence_moire") == 0
    assert spread("picket_fence_moire_21") >= 1


# --- interpenetrating pair ----------------------------------------------------------


def test_interpenetrating_planes_cross_inside_the_overlap():
    scene = shipped("interpenetrating")
    flat, tilted = scene.polygons
    overlap = outline(flat).intersection(outline(tilted))
    x, y = np.asarray(overlap.exterior.coords).T
    a, b, c = tilted.plane
    depth_gap = a * x + b * y + c - flat.plane[2]
    assert depth_gap.min() < -1 and depth_gap.max() > 1


# --- fan, abutting polygons, polygons beyond the image --------------------------------


def test_fan_apex_pixel_holds_every_wedge():
    scene = shipped("fan")
    assert len(scene.polygons) >= 24
    apexes = {tuple(p.vertices[0, :2]) for p in scene.polygons}
    assert len(apexes) == 1
    ax, ay = apexes.pop()
    colours = {tuple(p.color) for p in scene.polygons}
    assert len(colours) == len(scene.polygons)
    frags = visible_fragments(scene)
    at = frags.pixel == int(ay) * scene.width + int(ax)
    assert set(frags.polygon[at].tolist()) == {p.index for p in scene.polygons}
    assert frags.area[at].sum() == pytest.approx(1.0, abs=1e-12)


def test_abutting_polygons_leave_no_seam():
    scene = shipped("abutting")
    union = shapely.union_all([outline(p) for p in scene.polygons])
    inside = np.abs(area_per_pixel(scene, union) - 1.0) <= 1e-12
    shared_edge = shapely.LineString(scene.polygons[0].xy[[0, 2]])
    assert shared_edge.equals(shapely.LineString(scene.polygons[1].xy[[0, 1]]))
    seam = area_per_pixel(scene, shared_edge.buffer(1e-9))
    fully_inside_seam = inside & (seam > 0)
    assert fully_inside_seam.sum() >= 10
    np.testing.assert_allclose(catmull(scene)[fully_inside_seam], 1.0, rtol=0, atol=1e-12)


def test_beyond_image_scene_reaches_out_on_every_side():
    scene = shipped("beyond_image")
    xy = np.vstack([p.xy for p in scene.polygons])
    assert xy[:, 0].min() < 0 and xy[:, 1].min() < 0
    assert xy[:, 0].max() > scene.width and xy[:, 1].max() > scene.height
    image_box = shapely.box(0, 0, scene.width, scene.height)
    assert any(not outline(p).intersects(image_box) for p in scene.polygons)


# --- generators ---------------------------------------------------------------------

GENERATED = {
    "random_triangles": lambda seed: random_triangles(40, 64, 48, size=12.0, seed=seed),
    "random_polygons": lambda seed: random_polygons(15, 64, 48, size=20.0, seed=seed),
}


def scene_arrays(scene: Scene):
    return (
        scene.width,
        scene.height,
        scene.frames,
        scene.background.tolist(),
        scene.translate.tolist(),
        [(p.vertices.tolist(), p.color.tolist()) for p in scene.polygons],
    )


@pytest.mark.parametrize("name", sorted(GENERATED))
def test_generator_is_reproducible_by_seed(name):
    make = GENERATED[name]
    assert scene_arrays(make(7)) == scene_arrays(make(7))
    assert scene_arrays(make(7)) != scene_arrays(make(8))


def test_random_triangles_interpenetrate():
    scene = random_triangles(200, 64, 64, size=16.0, depth_range=(0.0, 10.0), seed=3)
    assert len(scene.polygons) == 200
    assert all(len(p.vertices) == 3 for p in scene.polygons)
    z = np.array([p.vertices[:, 2] for p in scene.polygons])
    assert z.min() >= 0.0 and z.max() <= 10.0
    assert (np.ptp(z, axis=1) > 0).all(), "every triangle is tilted"
    # some overlapping pair has depth planes that cross inside the overlap
    crossing = 0
    for i in range(20):
        for j in range(i + 1, 200):
            pi, pj = scene.polygons[i], scene.polygons[j]
            overlap = outline(pi).intersection(outline(pj))
            if overlap.area > 0.5:
                x, y = np.asarray(shapely.get_coordinates(overlap)).T
                gap = (pi.plane - pj.plane) @ np.vstack([x, y, np.ones_like(x)])
                crossing += gap.min() < 0 < gap.max()
    assert crossing >= 5


def test_random_triangles_benchmark_size_builds():
    scene = random_triangles(2000, 512, 512, seed=0)
    assert (scene.width, scene.height, len(scene.polygons)) == (512, 512, 2000)


def test_random_polygons_are_simple_and_often_concave():
    scene = random_polygons(60, 128, 128, vertices=(5, 12), seed=11)
    outlines = [outline(p) for p in scene.polygons]
    assert all(o.is_valid and o.area > 0 for o in outlines)
    assert all(5 <= len(p.vertices) <= 12 for p in scene.polygons)
    concave = sum(o.convex_hull.area - o.area > 1e-9 * o.area for o in outlines)
    assert concave >= 30
    assert sum(np.ptp(p.vertices[:, 2]) > 0 for p in scene.polygons) >= 55


def test_random_polygons_fragments_cover_every_pixel_once():
    # exact area conservation on interpenetrating concave polygons
    scene = random_polygons(12, 32, 32, size=14.0, seed=5)
    frags = visible_fragments(scene)
    per_pixel = np.bincount(frags.pixel, weights=frags.area, minlength=32 * 32)
    np.testing.assert_allclose(per_pixel, 1.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("n", [3, 7, 24, 64])
def test_fan_generator(n):
    scene = fan(n, 32, 32)
    assert len(scene.polygons) == n
    assert len({tuple(p.color) for p in scene.polygons}) == n
    union = shapely.union_all([outline(p) for p in scene.polygons])
    total = sum(outline(p).area for p in scene.polygons)
    assert union.area == pytest.approx(total, rel=1e-12), "wedges must not overlap"
    assert isinstance(union, shapely.Polygon), "wedges abut with no gaps"
    gapped = fan(n, 32, 32, gap=0.5, radius=10.0)
    wedge = 0.5 * 10.0**2 * np.sin(0.5 * 2 * np.pi / n)  # triangle with two sides r, angle between
    assert sum(outline(p).area for p in gapped.polygons) == pytest.approx(n * wedge, rel=1e-12)


def test_slivers_generator():
    scene = slivers(0.1, 32, 32, n=6, length=20.0)
    assert len(scene.polygons) == 6
    for p in scene.polygons:
        assert outline(p).area == pytest.approx(0.1 * 20.0, rel=1e-12)
        assert outline(p).minimum_rotated_rectangle.length == pytest.approx(2 * (20.0 + 0.1), rel=1e-9)
    with pytest.raises(ValueError):
        slivers(0.0)


def test_picket_fence_generator_stays_inside_the_image():
    scene = picket_fence(0.25, 1.1, bars=10, width=16, height=4, frames=8)
    box = shapely.box(0, 0, 16, 4)
    for k in range(scene.frames):
        assert all(box.contains(outline(p)) for p in scene.at_frame(k).polygons)
    assert scene.translate.tolist() == [1.1 / 8, 0.0]
    with pytest.raises(ValueError, match="do not fit"):
        picket_fence(0.3, 1.3, bars=40, width=32)


@pytest.mark.parametrize("bad", [0, -1, 2.5, True])
def test_generators_refuse_bad_counts(bad):
    with pytest.raises(ValueError):
        random_triangles(bad)


# --- write_scene --------------------------------------------------------------------

ROUND_TRIP = {
    "random_triangles": lambda: random_triangles(30, 40, 30, seed=1),
    "random_polygons": lambda: random_polygons(10, 40, 30, seed=2),
    "fan": lambda: fan(24),
    "slivers": lambda: slivers(0.05),
    "picket_fence": lambda: picket_fence(),
    "background_and_odd_floats": lambda: parse_scene(
        {
            "image": {"width": 5, "height": 7, "background": [0.1, 1e-300, 1 / 3]},
            "animation": {"frames": 3, "translate": [1 / 3, -1e-17]},
            "polygons": [{"color": [0.1, 0.2, 0.3], "vertices": [[0.1, 0.2, -0.0], [1e-7, 3, 4], [2, 0, 5e-324]]}],
        }
    ),
    "no_polygons": lambda: parse_scene({"image": {"width": 1, "height": 1}}),
}


@pytest.mark.parametrize("name", sorted(ROUND_TRIP))
def test_write_scene_round_trips(name, tmp_path):
    scene = ROUND_TRIP[name]()
    path = write_scene(scene, tmp_path / f"{name}.toml", comment="a test scene\nsecond line")
    back = load_scene(path)
    assert scene_arrays(back) == scene_arrays(scene)
    assert path.read_text().startswith("# a test scene\n# second line\n")
    # writing what was read gives the same file
    again = write_scene(back, tmp_path / "again.toml", comment="a test scene\nsecond line")
    assert again.read_text() == path.read_text()


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_shipped_scenes_round_trip(path, tmp_path):
    scene = load_scene(path)
    assert scene_arrays(load_scene(write_scene(scene, tmp_path / "s.toml"))) == scene_arrays(scene)


def test_write_scene_of_a_dict_validates_first_and_keeps_the_old_file(tmp_path):
    target = tmp_path / "scene.toml"
    target.write_text("old")
    bad = {"image": {"width": 4, "height": 4}, "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [1, 1, 0]]}]}
    with pytest.raises(SceneError, match="at least 3 vertices"):
        write_scene(bad, target)
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["scene.toml"], "no temporary file left behind"
    good = {"image": {"width": 4, "height": 4}, "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [1, 1, 0], [0, 2, 0]]}]}
    write_scene(good, target)
    assert load_scene(target).polygons[0].vertices.tolist() == [[0, 0, 0], [1, 1, 0], [0, 2, 0]]


def test_write_scene_writes_an_animated_scene_from_its_first_frame(tmp_path):
    # frame 5 holds translated vertices; moving them back to frame 0 rounds (x + 5t - 5t)
    scene = picket_fence()
    back = load_scene(write_scene(scene.at_frame(5), tmp_path / "f.toml"))
    assert back.frame == 0 and back.frames == scene.frames
    np.testing.assert_array_equal(back.translate, scene.translate)
    for p, q in zip(back.polygons, scene.polygons):
        np.testing.assert_allclose(p.vertices, q.vertices, rtol=0, atol=1e-13)


def test_scene_to_dict_refuses_extensions():
    scene = fan(3)
    from dataclasses import replace

    with pytest.raises(ValueError, match="extension"):
        scene_to_dict(replace(scene, extensions={"lights": []}))


@pytest.mark.parametrize(
    "make",
    [lambda: random_triangles(25, 24, 20, size=10.0, depth_range=(0.0, 5.0), seed=4),
     lambda: random_polygons(8, 24, 20, size=12.0, depth_range=(0.0, 5.0), seed=4)],
    ids=["random_triangles", "random_polygons"],
)
def test_generated_interpenetrating_scenes_render_exactly(make):
    scene = make()
    np.testing.assert_allclose(catmull(scene), oracle_image(scene), rtol=0, atol=1e-9)
