"""The reference cache gives back what went in, and reads every entry as untrusted input."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from aaeval.sweeps import load_experiment, run_sweep
from aaeval.sweeps.reference_cache import CacheEntryError, ReferenceCache, ReferenceInfo
from aaeval.sweeps.typed_json import decode_float, dumps, encode
from aaeval.metrics.temporal import intensity_sum
from tests.helpers.sweep_util import write_config

# NaN: not measured; the noise strata of an exact truth are 0, or NaN where nothing pools
noise = st.one_of(st.just(math.nan), st.floats(0.0, 2.0))
strata = st.tuples(noise, noise, noise)


@st.composite
def entries(draw):
    h, w = draw(st.integers(1, 5)), draw(st.integers(1, 5))
    image = draw(st.lists(st.floats(0.0, 1.0), min_size=h * w * 3, max_size=h * w * 3).map(
        lambda v: np.array(v, dtype=np.float64).reshape(h, w, 3)))
    info = ReferenceInfo(
        spec=draw(st.sampled_from(["catmull", "mitsuba:seed=0,spp=4096", "NaN"])),
        render_s=draw(st.floats(0.0, 100.0)), noise_rmse=draw(noise),
        noise_spec=draw(st.one_of(st.none(), st.just("mitsuba:seed=1,spp=4096"))),
        noise_by_metric=draw(st.one_of(st.none(), st.just({}), st.dictionaries(
            st.sampled_from(["rmse", "edge_rmse", "highlight_rmse"]), strata))),
        intensity_sum=intensity_sum(image), host=draw(st.text(max_size=8)))
    return image, info


def _same(a: ReferenceInfo, b: ReferenceInfo) -> bool:
    """Equal, NaN equal to NaN, None only to None."""
    return json.dumps(a.to_json(), sort_keys=True) == json.dumps(b.to_json(), sort_keys=True)


@settings(max_examples=60, deadline=None)
@given(entries())
def test_every_entry_comes_back_as_it_went_in(tmp_path_factory, entry):
    image, info = entry
    cache = ReferenceCache(tmp_path_factory.mktemp("cache"))
    cache.put("k", image, info)
    got_image, got = cache.get("k", image.shape)
    np.testing.assert_array_equal(got_image, image)
    assert got_image.dtype == np.float64 and got_image.shape == image.shape
    assert _same(got, info)
    for name in ("noise_rmse", "render_s"):
        assert (math.isnan(getattr(got, name)) and math.isnan(getattr(info, name))) or \
            getattr(got, name) == getattr(info, name)
    assert (got.noise_by_metric is None) == (info.noise_by_metric is None)


@given(st.recursive(st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True), st.integers(),
                              st.text(max_size=5)),
                    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=3), inner, max_size=3),
                    max_leaves=10))
def test_typed_json_is_strict_and_keeps_nan_inf_and_none_apart(value):
    text = dumps(value)
    back = json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} is not strict JSON"))

    def check(original, stored):
        if isinstance(original, float):
            got = decode_float(stored)
            assert (math.isnan(got) and math.isnan(original)) or got == original
        elif original is None:
            assert stored is None
        elif isinstance(original, list):
            assert len(stored) == len(original)
            for a, b in zip(original, stored):
                check(a, b)
        elif isinstance(original, dict):
            for k in original:
                check(original[k], stored[k])
        else:
            assert stored == original

    check(value, back)


def test_numpy_values_and_tuples_encode_as_plain_json():
    assert encode({"a": np.float32(np.inf), "b": (np.int64(3), np.array([np.nan, 1.0]))}) == \
        {"a": "Infinity", "b": [3, ["NaN", 1.0]]}


def _encode_by_protocol(obj):
    """The typed-JSON rules, case by case by protocol: the oracle for :func:`encode`'s
    shortcuts by exact type."""
    match obj:
        case Mapping():
            return {str(k): _encode_by_protocol(v) for k, v in obj.items()}
        case list() | tuple():
            return list(map(_encode_by_protocol, obj))
        case np.ndarray():
            return _encode_by_protocol(obj.tolist())
        case np.generic():
            return _encode_by_protocol(obj.item())
        case float() if math.isnan(obj):
            return "NaN"
        case float() if math.isinf(obj):
            return "Infinity" if obj > 0 else "-Infinity"
        case _:
            return obj


class _Key(str):
    def __str__(self):
        return f"key {super().__str__()}"


_scalars = st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
                     st.text(max_size=4), st.floats(width=32).map(np.float32), st.floats().map(np.float64),
                     st.integers(-2**63, 2**63 - 1).map(np.int64), st.booleans().map(np.bool_))
_keys = st.one_of(st.text(max_size=3), st.integers(-5, 5), st.booleans(), st.none(), st.floats(),
                  st.text(max_size=3).map(_Key), st.integers(-5, 5).map(np.int64))


@settings(max_examples=300, deadline=None)
@given(st.recursive(_scalars, lambda inner: st.lists(inner, max_size=3) | st.lists(inner, max_size=3).map(tuple)
                    | st.dictionaries(_keys, inner, max_size=3) | st.lists(st.floats(), max_size=3).map(np.array)
                    | st.dictionaries(st.text(max_size=3), inner, max_size=3).map(MappingProxyType),
                    max_leaves=12))
def test_encode_gives_the_bytes_of_the_typed_json_rules(value):
    expected = json.dumps(_encode_by_protocol(value), allow_nan=False, indent=1)
    assert dumps(value, indent=1) == expected


def test_a_cell_record_encodes_by_the_typed_json_rules(tmp_path):
    from aaeval.sweeps import SweepStore

    record = {"key": "k0", "metrics": {"psnr": math.inf, "rmse": np.float64(np.nan), "flip": np.float32(0.25),
                                       "ssim": None}, "frame": np.int64(3), "size": (24, 24),
              "reference_noise": {"rmse": -math.inf}, "options": {"k": 4, "exact": np.bool_(True)}}
    SweepStore(tmp_path).write_cell(record, None)
    expected = json.dumps(_encode_by_protocol(record), allow_nan=False, indent=1) + "\n"
    assert (tmp_path / "cells" / "k0.json").read_text() == expected


def _entry(tmp_path):
    image = np.full((4, 4, 3), 0.5)
    info = ReferenceInfo("catmull:shading=exact", 0.1, 1e-14, None, {"rmse": (0.0, math.nan, 0.0)},
                         intensity_sum(image), "h")
    cache = ReferenceCache(tmp_path)
    cache.put("k", image, info)
    return cache, image


@pytest.mark.parametrize("edit, why", [
    (lambda d: d.update(noise_rmse="Infinity"), "noise_rmse"),
    (lambda d: d.update(noise_rmse=1e308), "noise_rmse"),
    (lambda d: d.update(noise_rmse="loud"), "noise_rmse"),
    (lambda d: d.update(noise_rmse=None), "noise_rmse"),
    (lambda d: d.update(noise_by_metric={"rmse": ["0", 0, 0]}), "noise_by_metric"),
    (lambda d: d.update(noise_by_metric={"rmse": [-1.0, 0, 0]}), "noise_by_metric"),
    (lambda d: d.update(noise_by_metric={"rmse": [0, 0]}), "noise_by_metric"),
    (lambda d: d.update(noise_by_metric=[1, 2, 3]), "noise_by_metric"),
    (lambda d: d.update(intensity_sum=1.0), "intensity_sum"),
    (lambda d: d.update(render_s=True), "render_s"),
    (lambda d: d.update(host=3), "host"),
    (lambda d: d.pop("spec"), "missing"),
    (lambda d: d.update(extra=1), "unknown"),
])
def test_a_damaged_note_is_named_once_and_rendered_again(tmp_path, capsys, edit, why):
    cache, image = _entry(tmp_path)
    note = json.loads((tmp_path / "k.json").read_text())
    edit(note)
    (tmp_path / "k.json").write_text(json.dumps(note))
    assert cache.get("k", image.shape) is None
    assert cache.get("k", image.shape) is None
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(tmp_path / "k.npy") in err[0] and why in err[0], err


def test_damaged_images_are_rendered_again_without_reading_their_data(tmp_path, capsys):
    cache, image = _entry(tmp_path)
    np.save(tmp_path / "k.npy", np.full((4, 4, 3), np.nan))
    assert cache.get("k", image.shape) is None  # a NaN image never reaches a metric
    # a header that claims a huge image is refused from the header, before any data is read
    with open(tmp_path / "k.npy", "wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False, "shape": (12000, 12000, 3)})
    assert cache.get("k", None) is None
    assert cache.get("k", image.shape) is None
    os.unlink(tmp_path / "k.npy")
    os.mkfifo(tmp_path / "k.npy")  # reading a FIFO would block forever
    assert cache.get("k", image.shape) is None
    cache.put("k", image, ReferenceInfo("catmull", 0.1, 0.0, None, None, intensity_sum(image), "h"))
    assert cache.get("k", image.shape) is not None  # the new render replaced the damaged entry
    assert capsys.readouterr().err.count("damaged reference cache entry") == 1  # one path, named once


def test_a_link_in_the_cache_is_not_followed(tmp_path):
    cache, image = _entry(tmp_path)
    outside = tmp_path / "outside.json"
    os.replace(tmp_path / "k.json", outside)
    os.symlink(outside, tmp_path / "k.json")
    assert cache.get("k", image.shape) is None
    cache.put("k", image, ReferenceInfo("catmull", 0.1, 0.0, None, None, intensity_sum(image), "h"))
    assert not os.path.islink(tmp_path / "k.json") and json.loads(outside.read_text())["spec"] == "catmull:shading=exact"


def test_reference_info_refuses_a_noise_beyond_its_image():
    image = np.zeros((2, 2, 3))
    with pytest.raises(CacheEntryError, match="noise_rmse"):
        ReferenceInfo("m", 0.1, math.inf, None, None, 0.0, "h").check_against(image)


SHADED_AND_FLAT = """
[experiment]
name = "cached"
description = "a second sweep reads every reference from the cache"
reference = "jitter:k=2,seed=1"
metrics = ["rmse", "edge_rmse", "psnr"]
temporal = ["sum_variation", "flicker"]

[[groups]]
name = "flat"
scenes = [{generator = "edges", difficulty = [0.2], size = 10}]
animate = { frames = 2, phases = "random", seed = 1 }
methods = ["point", "catmull", "jitter:seed=3"]

[[groups]]
name = "shaded"
reference = "catmull:shading=exact"
metrics = ["rmse", "highlight_rmse"]
temporal = ["sum_variation", "highlight_profile_flicker"]
scenes = [{generator = "shininess", difficulty = [200], size = 10, frames = 2}]
methods = ["catmull", "jitter:k=2,seed=1"]
options.catmull = { specular = ["none", "amanatides"] }
"""


@pytest.mark.slow
def test_a_sweep_from_the_cache_gives_the_table_of_one_that_rendered(tmp_path):
    experiment = load_experiment(write_config(tmp_path, SHADED_AND_FLAT))
    first = run_sweep(experiment, tmp_path / "one", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    second = run_sweep(experiment, tmp_path / "two", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert first.references_rendered > 0 and second.references_cached == first.references_rendered
    assert second.references_rendered == 0
    assert first.failed == second.failed == 0 and not first.errors and not second.errors
    one, two = (pd.read_parquet(tmp_path / d / "results.parquet").sort_values("key").reset_index(drop=True)
                for d in ("one", "two"))
    varying = {"render_s", "render_s_min", "render_s_max", "ms_per_mpix", "pid", "finished_at"}
    pd.testing.assert_frame_equal(one.drop(columns=list(varying)), two.drop(columns=list(varying)))
    for folder in ("one", "two"):  # every JSON file of a sweep folder is strict JSON
        for path in (tmp_path / folder).rglob("*.json"):
            json.loads(path.read_text(), parse_constant=lambda c, p=path: pytest.fail(f"{p} holds {c}"))


def _gt_entry(tmp_path, monkeypatch):
    from aaeval.groundtruth import cache as gt
    from aaeval.scenes import load_scene

    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = load_scene("configs/scenes/fan.toml")
    path = gt.groundtruth_path(scene, spp=4, sampler="independent", seed=0)
    path.parent.mkdir(parents=True)
    return gt, scene, path


@pytest.mark.parametrize("damage", ["nan pixels", "huge header", "fifo", "wrong member"])
def test_a_damaged_ground_truth_entry_is_named_and_not_read_whole(tmp_path, monkeypatch, damage):
    gt, scene, path = _gt_entry(tmp_path, monkeypatch)
    if damage == "nan pixels":
        np.savez(path, image=np.full(scene.shape, np.nan))
    elif damage == "huge header":  # a few bytes claiming 12000 x 12000 x 3 float64
        import io
        import zipfile

        head = io.BytesIO()
        np.lib.format.write_array_header_1_0(head, {"descr": "<f8", "fortran_order": False,
                                                    "shape": (12000, 12000, 3)})
        with zipfile.ZipFile(path, "w") as z:
            z.writestr("image.npy", head.getvalue() + b"\0" * 64)
    elif damage == "fifo":
        os.mkfifo(path)
    else:
        np.savez(path, picture=np.zeros(scene.shape))
    with pytest.warns(UserWarning, match=f"damaged ground-truth cache entry {path}"):
        assert gt._read(path, scene) is None


def test_a_sound_ground_truth_entry_reads_back_exactly(tmp_path, monkeypatch):
    gt, scene, path = _gt_entry(tmp_path, monkeypatch)
    image = np.random.default_rng(0).random(scene.shape)
    np.savez(path, image=image)
    got, specular = gt._read(path, scene)
    np.testing.assert_array_equal(got, image)
    assert specular is None
