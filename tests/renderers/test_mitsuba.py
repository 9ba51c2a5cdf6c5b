"""The ``mitsuba`` ground truth against the exact ``catmull`` image, within measured noise.

Mitsuba is independent of aaeval's Catmull kernel (ray casting of ear-cut triangles in
float32 vs analytic clipping in float64), so agreement within the noise that Mitsuba's
own seeds show is evidence for both. Tolerances come from that measured noise, never
from a fixed number.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import pytest

from aaeval.renderers.check import MethodFailure

from aaeval.groundtruth import cache as gt_cache
from aaeval.groundtruth import flat as gt
from aaeval import mitsuba_variant as gv
from aaeval.renderers import render, resolve
from aaeval.scenes import parse_scene
from tests.helpers.mitsuba_util import FLOAT32_FLOOR, exact, mixed_scene, noise_statistics, poly, seeds


@pytest.mark.parametrize("size", [(32, 24), (17, 29)], ids=["wide", "tall"])
@pytest.mark.parametrize("sampler", gt.SAMPLERS)
def test_agrees_with_catmull_within_measured_noise(size, sampler):
    scene = mixed_scene(*size)
    reference = exact(scene)
    images = seeds(scene, 8, spp=16, sampler=sampler)
    single, averaged, variance, k = noise_statistics(images, reference)
    assert variance > 1e-6, "no measurable noise: the test would prove nothing"
    # one render: its squared error is about the variance (a few sigma of slack)
    assert single <= 2.0 * variance + FLOAT32_FLOOR
    # no bias: averaging k seeds divides the squared error by about k
    assert averaged <= 2.5 * variance / k + FLOAT32_FLOOR


def test_noise_check_catches_a_half_pixel_shift():
    # the statistics above must be able to fail: a reference moved by half a pixel does
    scene = mixed_scene()
    moved = dataclasses.replace(scene, translate=np.array([0.5, 0.0]), frames=2).at_frame(1)
    images = seeds(scene, 8, spp=16)
    _, averaged, variance, k = noise_statistics(images, exact(moved))
    assert averaged > 5 * variance / k


def test_converges_towards_catmull():
    scene = mixed_scene()
    reference = exact(scene)
    errors = [np.sqrt(np.mean((gt.render_mitsuba(scene, spp=spp) - reference) ** 2)) for spp in (16, 256, 4096)]
    # stratified converges at least as N^-1/2 (N^-3/4 on edges): x16 spp, >= 4x less error
    assert errors[1] < errors[0] / 4 and errors[2] < errors[1] / 4


@pytest.mark.parametrize("width,height", [(8, 4), (4, 8), (5, 5)])
def test_pixel_mapping_and_orientation(width, height):
    # whole-pixel squares are exact whatever the samples: each must land on its pixel
    squares = [(0, 1, [1, 0, 0]), (height - 1, width - 2, [0, 0.5, 0]), (height // 2, 0, [0, 0, 0.25])]
    scene = parse_scene(
        {
            "image": {"width": width, "height": height},
            "polygons": [poly(c, [[col, row], [col + 1, row], [col + 1, row + 1], [col, row + 1]], 0, 0, 1) for row, col, c in squares],
        }
    )
    image = gt.render_mitsuba(scene, spp=4)
    expected = np.zeros((height, width, 3))
    for row, col, c in squares:
        expected[row, col] = c
    np.testing.assert_array_equal(image, expected)
    np.testing.assert_array_equal(image, exact(scene))


@pytest.mark.parametrize("order", [(0, 1), (1, 0)])
def test_coplanar_overlap_later_polygon_in_front(order):
    # two polygons on one tilted plane, overlapping on whole pixels: the later one wins
    colors = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    outlines = [[[1, 1], [6, 1], [6, 5], [1, 5]], [[3, 2], [8, 2], [8, 6], [3, 6]]]
    scene = parse_scene(
        {
            "image": {"width": 10, "height": 7, "background": [0, 0, 1]},
            "polygons": [poly(colors[i], outlines[i], 0.37, -0.21, 3.0) for i in order],
        }
    )
    image = gt.render_mitsuba(scene, spp=4)
    np.testing.assert_array_equal(image, exact(scene))
    assert (image[3, 4] == colors[order[1]]).all()


def test_empty_scene_is_background_and_edge_on_polygons_cover_nothing():
    empty = parse_scene({"image": {"width": 5, "height": 3, "background": [0.25, 0.5, 0.75]}})
    np.testing.assert_array_equal(gt.render_mitsuba(empty, spp=4), np.broadcast_to([0.25, 0.5, 0.75], (3, 5, 3)))
    edge_on = parse_scene(
        {
            "image": {"width": 5, "height": 3, "background": [0.25, 0.5, 0.75]},
            "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [2.5, 1.5, 1], [5, 3, 3]]}],
        }
    )
    assert len(gt.triangulate_scene(edge_on).faces) == 0
    np.testing.assert_array_equal(gt.render_mitsuba(edge_on, spp=4), exact(edge_on))


def test_triangulation_covers_each_polygon_once():
    scene = mixed_scene()
    tri = gt.triangulate_scene(scene, margin=1e9)  # nothing clipped
    v = tri.vertices
    a, b, c = (v[tri.faces[:, i], :2] for i in range(3))
    areas = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    for p in scene.polygons:
        xy = p.xy
        shoelace = 0.5 * abs(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]))
        assert areas[tri.polygon == p.index].sum() == pytest.approx(shoelace, rel=1e-9)


def test_camera_depths_keep_the_order_of_scene_depths():
    z = np.array([-1e6, -3.0, 0.0, 2.5, 7e8])
    depth = gt.camera_depths(z, z.min(), z.max())
    assert np.all(np.diff(depth) > 0)
    assert depth[0] == gt.NEAR and depth[-1] == gt.NEAR + gt.DEPTH_SPAN
    assert gt.camera_depths(np.array([5.0]), 5.0, 5.0, rank=2)[0] < gt.camera_depths(np.array([5.0]), 5.0, 5.0)[0]


def test_clip_keeps_far_vertices_out_of_float32():
    scene = mixed_scene()
    tri = gt.triangulate_scene(scene)
    assert tri.vertices[:, 0].min() >= -gt.MARGIN and tri.vertices[:, 0].max() <= scene.width + gt.MARGIN
    assert tri.vertices[:, 1].min() >= -gt.MARGIN and tri.vertices[:, 1].max() <= scene.height + gt.MARGIN


def test_row_bands_match_one_pass(monkeypatch):
    scene = mixed_scene()
    whole = gt.render_mitsuba(scene, spp=64, seed=3)
    monkeypatch.setattr(gt, "MAX_SAMPLES_PER_PASS", scene.width * 64 * 5)
    assert len(gt.row_bands(scene.width, scene.height, 64)) == 5
    banded = gt.render_mitsuba(scene, spp=64, seed=3)
    band0 = slice(0, 5)  # band 0 keeps the seed and the same samples
    np.testing.assert_array_equal(banded[band0], whole[band0])
    reference = exact(scene)
    assert np.mean((banded - reference) ** 2) < 4 * np.mean((whole - reference) ** 2) + FLOAT32_FLOOR


def test_extension_tables_are_refused():
    scene = dataclasses.replace(mixed_scene(), extensions={"phong": {}})
    with pytest.raises(ValueError, match="phong"):
        gt.render_mitsuba(scene, spp=4)


# --- the registered method and its cache ---------------------------------------------


def test_method_is_registered_with_its_options():
    method, options = resolve("mitsuba")
    assert options == {"spp": 16384, "sampler": "multijitter", "seed": 0, "variant": "auto", "cache": True, "filter": "box"}
    with pytest.raises(ValueError):
        resolve("mitsuba:sampler=halton")
    with pytest.raises(ValueError):
        resolve("mitsuba:radius=2")


def test_cache_second_request_does_not_render(tmp_path, monkeypatch):
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = mixed_scene()
    first = render(scene, "mitsuba:spp=16,seed=2")
    files = sorted(p.name for p in (tmp_path / "groundtruth").iterdir())
    assert len(files) == 2 and files[0].endswith(".json") and files[1].endswith(".npz")

    def no_render(*args, **kwargs):
        raise AssertionError("rendered although the image was cached")

    monkeypatch.setattr(gt, "render_mitsuba", no_render)
    image, hit = gt_cache.groundtruth_image(scene, spp=16, seed=2)
    assert hit
    np.testing.assert_array_equal(image, first)
    # the file path is not part of the key; the options that change pixels are
    renamed = dataclasses.replace(scene, source="elsewhere.toml")
    assert gt_cache.groundtruth_image(renamed, spp=16, seed=2)[1]
    with pytest.raises(AssertionError, match="rendered"):
        gt_cache.groundtruth_image(scene, spp=16, seed=3)
    with pytest.raises(MethodFailure, match="rendered"):  # through the method boundary: one line
        render(scene, "mitsuba:spp=16,seed=2,cache=false")


def test_cache_key_follows_geometry_and_options():
    scene = mixed_scene()
    key = gt_cache.groundtruth_key(scene, spp=16, sampler="stratified", seed=0)
    moved = dataclasses.replace(scene, translate=np.array([0.25, 0.0]), frames=2)
    recoloured = parse_scene({"image": {"width": 32, "height": 24, "background": [0.1, 0.2, 0.31]}})
    assert key == gt_cache.groundtruth_key(moved, spp=16, sampler="stratified", seed=0)  # frame 0 is the same
    assert key != gt_cache.groundtruth_key(moved.at_frame(1), spp=16, sampler="stratified", seed=0)
    assert key != gt_cache.groundtruth_key(scene, spp=17, sampler="stratified", seed=0)
    assert key != gt_cache.groundtruth_key(scene, spp=16, sampler="independent", seed=0)
    assert gt_cache.scene_digest(recoloured) != gt_cache.scene_digest(
        parse_scene({"image": {"width": 32, "height": 24, "background": [0.1, 0.2, 0.3]}})
    )


def test_cache_key_follows_the_conversion_code(tmp_path, monkeypatch):
    """Editing the code that converts or shades a scene gives new keys (no version to bump)."""
    root = tmp_path / "pkg"
    for rel in gt_cache.CODE_FILES:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_bytes((gt_cache.Path(gt_cache.aaeval.__file__).parent / rel).read_bytes())
    before = gt_cache.code_digest(root=root)
    assert before == gt_cache.code_digest()  # the same sources
    with open(root / "groundtruth" / "flat.py", "a") as f:
        f.write("\nNEAR = 2.0\n")
    gt_cache.code_digest.cache_clear()  # computed once per process otherwise
    assert gt_cache.code_digest(root=root) != before
    scene = mixed_scene()
    key = gt_cache.groundtruth_key(scene, spp=16, sampler="stratified", seed=0)
    monkeypatch.setattr(gt_cache, "code_digest", lambda: "edited")
    assert gt_cache.groundtruth_key(scene, spp=16, sampler="stratified", seed=0) != key


def test_damaged_cache_entry_is_rendered_again_with_a_warning(tmp_path, monkeypatch):
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = mixed_scene(8, 6)
    first, _ = gt_cache.groundtruth_image(scene, spp=4, seed=1)
    path = gt_cache.groundtruth_path(scene, spp=4, sampler=gt.DEFAULT_SAMPLER, seed=1)
    path.write_bytes(path.read_bytes()[:40])  # truncated, as a power cut could leave it
    with pytest.warns(UserWarning, match="damaged ground-truth cache entry"):
        again, hit = gt_cache.groundtruth_image(scene, spp=4, seed=1)
    assert not hit
    np.testing.assert_array_equal(again, first)
    assert gt_cache.groundtruth_image(scene, spp=4, seed=1)[1]  # replaced by a sound entry


def test_cache_dir_default_and_override(monkeypatch, tmp_path):
    monkeypatch.delenv("AAEVAL_CACHE_DIR", raising=False)
    assert gt_cache.cache_dir() == gt_cache.Path.home() / ".cache" / "aaeval" / "groundtruth"
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    assert gt_cache.cache_dir() == tmp_path / "groundtruth"


# --- variant selection -----------------------------------------------------------------


def _touch(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"")
    return path


def test_find_libllvm_picks_newest_at_least_16(tmp_path):
    lib = tmp_path / "lib"
    for name in ["libLLVM-14.so", "libLLVM-14.0.6.so.1", "libLLVM-15.so.1", "libLLVM-17.so", "libLLVM.so.19.1", "libLLVMCore.a"]:
        _touch(lib / name)
    _touch(tmp_path / "llvm-18" / "lib" / "libLLVM.so")  # version from the folder
    found = gv.find_libllvm([str(lib), str(tmp_path / "llvm-*" / "lib")], env={})
    assert found == lib / "libLLVM.so.19.1"


def test_find_libllvm_skips_14_and_15(tmp_path):
    for name in ["libLLVM-14.so", "libLLVM-15.so", "libLLVM.so.15.0"]:
        _touch(tmp_path / name)
    _touch(tmp_path / "libLLVM.so")  # version unknown: not trusted
    assert gv.find_libllvm([str(tmp_path)], env={}) is None
    _touch(tmp_path / "llvm-16" / "lib" / "libLLVM.so")
    assert gv.find_libllvm([str(tmp_path), str(tmp_path / "llvm-*" / "lib")], env={}) == tmp_path / "llvm-16" / "lib" / "libLLVM.so"


def test_find_libllvm_honours_the_environment(tmp_path):
    _touch(tmp_path / "libLLVM-19.so")
    chosen = "/somewhere/libLLVM-15.so"
    assert gv.find_libllvm([str(tmp_path)], env={gv.LIBLLVM_ENV: chosen}) == gv.Path(chosen)


def test_libllvm_version_from_homebrew_cellar(tmp_path):
    real = _touch(tmp_path / "Cellar" / "llvm" / "19.1.7" / "lib" / "libLLVM.dylib")
    (tmp_path / "opt").mkdir()
    os.symlink(real.parent.parent, tmp_path / "opt" / "llvm")
    assert gv.libllvm_version(tmp_path / "opt" / "llvm" / "lib" / "libLLVM.dylib") == 19
    assert gv.libllvm_version("/opt/homebrew/opt/llvm@17/lib/libLLVM.dylib") == 17
    assert gv.libllvm_version("/usr/lib/x86_64-linux-gnu/libLLVM-14.0.6.so.1") == 14


def test_auto_variant_is_the_fastest_that_runs_here():
    variant = gv.select_variant()
    assert variant.endswith("_rgb")
    if not variant.startswith("cuda") and gv.find_libllvm() is not None:
        assert variant == "llvm_ad_rgb"


def test_unusable_variants_fail_clearly():
    with pytest.raises(gv.VariantError, match="not built"):
        gv.import_mitsuba("llvm_ad_nonsense")
    with pytest.raises(gv.VariantError, match="not an RGB"):
        gv.import_mitsuba("scalar_spectral")


def test_a_variant_set_elsewhere_is_switched_and_images_agree():
    # e.g. imageio sets scalar_rgb for EXR files; the ground truth must still render
    scene = mixed_scene(12, 9)
    reference = exact(scene)
    jit = gt.render_mitsuba(scene, spp=64, seed=1)
    mi = gv.import_mitsuba("scalar_rgb")
    scalar = gt.render_mitsuba(scene, spp=64, seed=1, variant="scalar_rgb")
    assert mi.variant() == "scalar_rgb"
    again = gt.render_mitsuba(scene, spp=64, seed=1)
    assert mi.variant() == gv.select_variant()
    np.testing.assert_array_equal(again, jit)
    # scalar draws other random numbers: it must agree in distribution, not bit for bit
    assert np.mean((scalar - reference) ** 2) < 4 * np.mean((jit - reference) ** 2) + FLOAT32_FLOOR


def test_falls_back_to_scalar_with_one_warning_when_nothing_faster_runs(tmp_path):
    # in a child process: the variant and Dr.Jit's backends are global to a process
    import subprocess
    import sys

    code = (
        "import warnings; warnings.simplefilter('error')\n"
        "from aaeval.mitsuba_variant import select_variant\n"
        "try:\n    select_variant()\nexcept RuntimeWarning as w:\n    print('WARNING', w)\n"
    )
    env = {
        **os.environ,
        gv.LIBLLVM_ENV: str(tmp_path / "libLLVM-19.so"),  # missing file
        "CUDA_VISIBLE_DEVICES": "",
        "PYTHONPATH": str(gv.Path(__file__).resolve().parents[2]),
    }
    result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    lines = [line for line in result.stdout.splitlines() if line.startswith("WARNING")]
    assert len(lines) == 1 and "scalar_rgb" in lines[0] and "libLLVM-19.so" in lines[0]


def test_coplanar_ranks_order_overlapping_polygons_only():
    square = [[0, 0], [4, 0], [4, 4], [0, 4]]
    moved = [[x + 10, y] for x, y in square]
    scene = parse_scene(
        {
            "image": {"width": 16, "height": 6},
            "polygons": [
                poly([1, 0, 0], square, 0.5, 0.25, 2),
                poly([0, 1, 0], moved, 0.5, 0.25, 2),  # same plane, elsewhere: no nudge
                poly([0, 0, 1], [[1, 1], [5, 1], [5, 5]], 0.5, 0.25, 2),  # on top of the first
                poly([1, 1, 0], [[2, 0], [3, 0], [3, 6]], 0.5, 0.25, 2),  # on top of both
                poly([1, 0, 1], square, 0.5, 0.25, 2.5),  # another plane
            ],
        }
    )
    np.testing.assert_array_equal(gt.coplanar_ranks(scene), [0, 0, 1, 2, 0])
