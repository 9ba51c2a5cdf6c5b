"""The scene checks that scale: many small polygons checked array-wide (holes.
_plain_polygons) give the polygons, planes included, bit for bit as the polygon-by-polygon
checks do, and every broken rule still gives the same one-line error; the holes of one
polygon are checked apart by a box sweep with the pairwise rules and errors."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import SceneError, parse_polygon
from aaeval.scenes.holes import PLAIN_BATCH_MIN


def plain_scene(n=200, seed=0, ks=(3, 4, 5, 6, 7)):
    rng = np.random.default_rng(seed)
    polys = []
    for i in range(n):
        k = ks[i % len(ks)]
        t = np.sort(rng.uniform(0, 2 * np.pi, k))
        centre = rng.uniform(0, 64, 2)
        xy = centre + rng.uniform(2, 9) * np.column_stack([np.cos(t), np.sin(t)])  # convex: simple
        a, b, c = rng.uniform(-1, 1, 3)
        z = a * xy[:, 0] + b * xy[:, 1] + 50 * c
        if i % 7 == 0:
            z = np.full(k, float(i))  # flat, integer depths
        verts = [[float(x), float(y), float(w)] for (x, y), w in zip(xy, z)]
        if i % 11 == 0:  # TOML integers
            x, y = (int(c) for c in rng.integers(0, 60, 2))
            verts = [[x, y, i], [x + 3, y, i], [x + 3, y + 3, i], [x, y + 3, i]]
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": verts})
    return {"image": {"width": 64, "height": 64}, "polygons": polys}


def one_by_one(document):
    return [parse_polygon(raw, i, "s") for i, raw in enumerate(document["polygons"])]


def same_bits(a, b):
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("seed", range(3))
def test_batch_gives_the_polygons_and_planes_bit_for_bit(seed):
    document = plain_scene(seed=seed)
    got = parse_scene(document, source="s").polygons  # the seeds give valid outlines: a refusal is a fault
    want = one_by_one(document)
    assert len(got) == len(want) >= PLAIN_BATCH_MIN
    for g, w in zip(got, want):
        assert g.index == w.index
        assert same_bits(g.vertices, w.vertices) and same_bits(g.color, w.color)
        assert same_bits(g.plane, w.plane), (g.index, g.plane, w.plane)


def test_batch_keeps_a_sliver_and_an_edge_on_polygon_as_the_single_checks_do():
    document = plain_scene(seed=5)
    document["polygons"][3]["vertices"] = [[0.0, 0.0, 1.0], [10.0, 1e-9, 1.0], [20.0, 0.0, 1.0]]  # sliver
    document["polygons"][4]["vertices"] = [[0.0, 0.0, 1.0], [10.0, 0.0, 2.0], [10.0, 0.0, 5.0]]  # edge-on
    got = parse_scene(document, source="s").polygons
    want = one_by_one(document)
    for k in (3, 4):
        assert same_bits(got[k].plane, want[k].plane)


BROKEN = [
    ("vertices", [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], "repeats vertex"),
    ("vertices", [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]], "degenerate polygon"),
    ("vertices", [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [2.0, 2.0, 0.0]], "self-crossing"),
    ("vertices", [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 1.0]], "not planar"),
    ("vertices", [[0.0, 0.0, 0.0], [True, 0.0, 0.0], [0.0, 1.0, 0.0]], "expected a number"),
    ("vertices", [[0.0, 0.0, 0.0], ["1", 0.0, 0.0], [0.0, 1.0, 0.0]], "expected a number"),
    ("vertices", [[0.0, 0.0, 0.0], [float("nan"), 0.0, 0.0], [0.0, 1.0, 0.0]], "non-finite"),
    ("vertices", [[0.0, 0.0, 0.0], [2e9, 0.0, 0.0], [0.0, 1.0, 0.0]], "beyond"),
    ("vertices", [[0.0, 0.0, 0.0], [1.0, 0.0], [0.0, 1.0, 0.0]], "expected a list of 3"),
    ("color", [0.5, 1.5, 0.0], "colour components"),
    ("color", [0.5, 0.5], "expected a list of 3"),
]


@pytest.mark.parametrize("key, value, words", BROKEN)
def test_a_broken_rule_in_a_large_scene_gives_the_single_polygon_error(key, value, words):
    document = plain_scene(seed=1)
    document["polygons"][150][key] = value
    document["polygons"][170]["vertices"] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]  # a later error
    with pytest.raises(SceneError) as got:
        parse_scene(document, source="s")
    with pytest.raises(SceneError) as want:
        parse_polygon(document["polygons"][150], 150, "s")
    assert str(got.value) == str(want.value)
    assert "polygons[150]" in str(got.value) and words in str(got.value)


# --- holes apart ---------------------------------------------------------------------


def holed(n, extra=None):
    side = int(np.ceil(np.sqrt(n)))
    holes = []
    for k in range(n):
        i, j = divmod(k, side)
        x, y = 2 + 3 * i, 2 + 3 * j
        holes.append([[x, y, 0.0], [x + 1, y, 0.0], [x + 1, y + 1, 0.0], [x, y + 1, 0.0]])
    if extra is not None:
        holes.append(extra)
    size = 3 * side + 4
    outer = [[0, 0, 0.0], [size, 0, 0.0], [size, size, 0.0], [0, size, 0.0]]
    return {"image": {"width": 16, "height": 16}, "polygons": [{"color": [1, 1, 1], "vertices": outer, "holes": holes}]}


def square(x, y, s):
    return [[x, y, 0.0], [x + s, y, 0.0], [x + s, y + s, 0.0], [x, y + s, 0.0]]


def test_many_holes_apart_are_accepted():
    scene = parse_scene(holed(400), source="s")
    assert len(scene.holed) == 1 and scene.holed[0].count > 400


@pytest.mark.parametrize("extra, words", [
    (square(2.5, 2.5, 1.0), "holes[400]: hole crosses or touches holes[0]"),
    (square(3.0, 2.0, 1.0), "holes[400]: hole crosses or touches holes[0]"),  # touches along an edge
    (square(2.25, 2.25, 0.5), "holes[400]: hole overlaps holes[0] (one lies inside the other)"),
    (square(1.5, 1.5, 2.0), "holes[400]: hole overlaps holes[0] (one lies inside the other)"),
    (square(200.0, 200.0, 1.0), "holes[400]: hole lies outside the outer ring"),
    (square(-0.5, 5.0, 1.0), "holes[400]: hole crosses or touches the outer ring"),
])
def test_a_hole_breaking_a_rule_among_many_gives_the_pairwise_error(extra, words):
    with pytest.raises(SceneError, match=r"polygons\[0\]\.") as got:
        parse_scene(holed(400, extra), source="s")
    assert words in str(got.value)


def test_the_first_broken_pair_is_named():
    # hole 400 overlaps hole 0, hole 401 overlaps hole 1: the pairwise order names (400, 0)
    document = holed(400, square(2.25, 2.25, 0.5))
    document["polygons"][0]["holes"].append(square(2.25, 5.25, 0.5))
    with pytest.raises(SceneError, match=r"holes\[400\]: hole overlaps holes\[0\]"):
        parse_scene(document, source="s")


# --- large files --------------------------------------------------------------------


def test_a_large_file_reads_as_tomllib_reads_it_and_fails_in_its_words(tmp_path, monkeypatch):
    # files of FAST_READER_BYTES and more go through rtoml when it is installed; the
    # document must be tomllib's, and any error tomllib's one line. The reader picks its
    # path by the file's size alone, so the threshold is lowered to 64 KiB here: the same
    # path on a 64 KiB file, a 16th of the seven tomllib reads of a 1 MiB one (8 s)
    import tomllib

    from aaeval import _toml
    from aaeval._toml import read_toml

    monkeypatch.setattr(_toml, "FAST_READER_BYTES", 1 << 16)
    FAST_READER_BYTES = _toml.FAST_READER_BYTES
    fast, fast_loads = [], _toml._fast_loads

    def spied_fast_loads(text):
        fast.append(len(text))
        return fast_loads(text)

    monkeypatch.setattr(_toml, "_fast_loads", spied_fast_loads)
    body = "".join(f'[[polygons]]\ncolor = [0.5, 0.25, 1]\nvertices = [[{k}, 0, 1e-3], [{k + 1}.5, 0, -2], [{k}, 1, 3]]\n'
                   for k in range(FAST_READER_BYTES // 60))
    good = tmp_path / "good.toml"
    good.write_text("[image]\nwidth = 8\nheight = 8\n" + body)
    assert good.stat().st_size >= FAST_READER_BYTES
    assert read_toml(good, SceneError, "scene file")[0] == tomllib.loads(good.read_text())
    assert fast == [good.stat().st_size]  # read by the fast reader, as a 1 MiB file is
    for bad_tail in ("x = = 1\n", "a = " + "[" * 3000 + "]" * 3000 + "\n", "color = [0, 0, 0]\n"):  # a repeated key
        bad = tmp_path / "bad.toml"
        bad.write_text(good.read_text() + bad_tail)
        with pytest.raises(SceneError) as got:
            read_toml(bad, SceneError, "scene file")
        try:
            tomllib.loads(bad.read_text())
            words = "nests arrays or tables too deeply"
        except tomllib.TOMLDecodeError as exc:
            words = str(exc)
        except RecursionError:
            words = "nests arrays or tables too deeply"
        assert words in str(got.value)
