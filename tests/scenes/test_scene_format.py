"""Every bad-input rule of the scene format (shared/SCENE_FORMAT.md, "Bad input").

A broken file is refused before any rendering with a message that names the file, the
polygon's index (for a polygon's fault) and the rule; ``aaeval render`` turns that into
exit code 2 and leaves an existing output file as it was.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from aaeval.cli import main
from aaeval.scenes import SceneError, load_scene

IMAGE = "[image]\nwidth = 8\nheight = 6\n"
GOOD = "\n[[polygons]]\ncolor = [1.0, 0.0, 0.0]\nvertices = [[0, 0, 0], [4, 0, 0], [0, 4, 0]]\n"


def with_bad_polygon(body: str) -> str:
    """A scene whose polygons 0 and 1 are fine and polygon 2 is ``body``."""
    return IMAGE + GOOD + GOOD + "\n[[polygons]]\n" + body + "\n"


# (name, file text, polygon index named in the message or None, words naming the rule)
CASES = [
    # missing keys
    ("missing image table", "[[polygons]]\ncolor = [1, 0, 0]\nvertices = [[0,0,0],[1,0,0],[0,1,0]]\n", None,
     "missing required table [image]"),
    ("missing width", "[image]\nheight = 4\n", None, "missing required key 'width'"),
    ("missing height", "[image]\nwidth = 4\n", None, "missing required key 'height'"),
    ("missing color", with_bad_polygon("vertices = [[0,0,0],[1,0,0],[0,1,0]]"), 2, "missing required key 'color'"),
    ("missing vertices", with_bad_polygon("color = [1, 0, 0]"), 2, "missing required key 'vertices'"),
    # wrong types
    ("width is a float", "[image]\nwidth = 4.0\nheight = 4\n", None, "'width' must be an integer"),
    ("height is a string", '[image]\nwidth = 4\nheight = "4"\n', None, "'height' must be an integer"),
    ("width is a boolean", "[image]\nwidth = true\nheight = 4\n", None, "'width' must be an integer"),
    ("image is not a table", "image = 3\n", None, "[image] must be a table"),
    ("animation is not a table", "animation = [1, 2]\n" + IMAGE, None, "[animation] must be a table"),
    ("frames is a float", IMAGE + "[animation]\nframes = 2.5\n", None, "'frames' must be an integer"),
    ("translate of one number", IMAGE + "[animation]\nframes = 2\ntranslate = [0.5]\n", None,
     "translate: expected a list of 2 numbers"),
    ("background of two numbers", "[image]\nwidth = 4\nheight = 4\nbackground = [0, 0]\n", None,
     "background: expected a list of 3 numbers"),
    ("polygons is a table", IMAGE + "[polygons]\ncolor = [1, 0, 0]\n", None, "must be an array of tables"),
    ("polygon is not a table", "polygons = [1, 2]\n" + IMAGE, 0, "must be a table"),
    ("color is a string", with_bad_polygon('color = "red"\nvertices = [[0,0,0],[1,0,0],[0,1,0]]'), 2,
     "color: expected a list of 3 numbers"),
    ("color of four numbers", with_bad_polygon("color = [1, 0, 0, 1]\nvertices = [[0,0,0],[1,0,0],[0,1,0]]"), 2,
     "color: expected a list of 3 numbers"),
    ("vertices is a number", with_bad_polygon("color = [1, 0, 0]\nvertices = 3"), 2,
     "expected a list of [x, y, z] points"),
    ("vertex of two numbers", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,0],[0,1,0]]"), 2,
     "vertices[1]: expected a list of 3 numbers"),
    ("vertex coordinate is a string", with_bad_polygon('color = [1, 0, 0]\nvertices = [[0,0,0],[1,0,0],[0,"1",0]]'),
     2, "vertices[2]: expected a number"),
    ("vertex coordinate is a boolean", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,false],[1,0,0],[0,1,0]]"),
     2, "vertices[0]: expected a number"),
    # fewer than 3 vertices
    ("two vertices", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,1,0]]"), 2,
     "at least 3 vertices, got 2"),
    ("no vertices", with_bad_polygon("color = [1, 0, 0]\nvertices = []"), 2, "at least 3 vertices, got 0"),
    # non-finite numbers
    ("nan vertex", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,0,nan],[0,1,0]]"), 2,
     "non-finite number"),
    ("infinite vertex", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[inf,0,0],[0,1,0]]"), 2,
     "non-finite number"),
    ("infinite color", with_bad_polygon("color = [1, -inf, 0]\nvertices = [[0,0,0],[1,0,0],[0,1,0]]"), 2,
     "non-finite number"),
    ("nan background", "[image]\nwidth = 4\nheight = 4\nbackground = [0, nan, 0]\n", None, "non-finite number"),
    ("infinite translate", IMAGE + "[animation]\nframes = 2\ntranslate = [inf, 0]\n", None, "non-finite number"),
    # non-planar
    ("non-planar quad", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,0],[4,4,1],[0,4,0]]"), 2,
     "not planar"),
    ("slightly non-planar quad",
     with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,0],[4,4,1e-6],[0,4,0]]"), 2, "not planar"),
    # self-crossing
    ("bow tie", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,4,0],[4,0,0],[0,6,0]]"), 2,
     "self-crossing"),
    ("pentagram", with_bad_polygon(
        "color = [1, 0, 0]\nvertices = [[2,0,0],[3.2,3.6,0],[0,1.4,0],[4,1.4,0],[0.8,3.6,0]]"), 2, "self-crossing"),
    ("vertex touching a far edge",
     with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,0],[2,2,0],[4,4,0],[0,4,0],[2,2,0]]"), 2,
     "self-crossing"),
    ("symmetric bow tie", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,4,0],[4,0,0],[0,4,0]]"),
     2, "self-crossing"),
    ("edge-on bow tie", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,4],[4,0,0],[0,0,4]]"),
     2, "self-crossing"),
    # repeated vertices and degenerate outlines
    ("repeated vertex", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,0],[4,0,0],[0,4,0]]"), 2,
     "vertex 2 repeats vertex 1"),
    ("closing vertex", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,0,0],[0,4,0],[0,0,0]]"), 2,
     "leave out the closing vertex"),
    ("collinear triangle", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,1,0],[3,3,0]]"), 2,
     "degenerate polygon"),
    ("collinear quad", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,1,1],[2,2,2],[3,3,3]]"), 2,
     "degenerate polygon"),
    ("huge coordinate", with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1e300,0,0],[0,1,0]]"), 2,
     "coordinates beyond"),
    ("huge image", "[image]\nwidth = 1000000\nheight = 1000000\n", None, "over the limit"),
    # non-positive size
    ("zero width", "[image]\nwidth = 0\nheight = 4\n", None, "'width' must be >= 1"),
    ("negative height", "[image]\nwidth = 4\nheight = -3\n", None, "'height' must be >= 1"),
    ("zero frames", IMAGE + "[animation]\nframes = 0\n", None, "'frames' must be >= 1"),
    # unknown keys
    ("unknown top-level table", IMAGE + "[camera]\nfov = 30\n", None, "unknown top-level key(s) ['camera']"),
    ("unknown image key", "[image]\nwidth = 4\nheight = 4\ndepth = 2\n", None, "unknown key(s) ['depth']"),
    ("unknown animation key", IMAGE + "[animation]\nframes = 2\nrotate = 1.0\n", None, "unknown key(s) ['rotate']"),
    ("unknown polygon key",
     with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[1,0,0],[0,1,0]]\nopacity = 0.5"), 2,
     "unknown key(s) ['opacity']"),
    # not a scene at all
    ("not TOML", "[image\nwidth = 4\n", None, "not valid TOML"),
]


PARAMS = [pytest.param(c, id=c[0]) for c in CASES]


@pytest.fixture(params=PARAMS)
def bad_scene(request, tmp_path):
    name, text, index, rule = request.param
    path = tmp_path / "bad scene.toml"
    path.write_text(text)
    return path, index, rule


def test_bad_scene_is_refused_naming_file_polygon_and_rule(bad_scene):
    path, index, rule = bad_scene
    with pytest.raises(SceneError) as caught:
        load_scene(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: "), message
    assert rule in message, message
    if index is not None:
        assert f"polygons[{index}]" in message, message


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(SceneError, match="cannot read scene file"):
        load_scene(tmp_path / "nowhere.toml")


def test_cases_cover_every_rule_of_the_format():
    rules = " ".join(rule for *_, rule in CASES)
    for words in ["missing required", "must be an integer", "at least 3 vertices", "non-finite",
                  "not planar", "self-crossing", ">= 1", "unknown key", "expected a list"]:
        assert words in rules


def test_good_polygons_around_the_bad_one_are_themselves_valid(tmp_path):
    # so the index in a message can only come from the bad polygon
    path = tmp_path / "good.toml"
    path.write_text(with_bad_polygon("color = [0, 1, 0]\nvertices = [[0,0,0],[4,0,0],[4,4,0],[0,4,0]]"))
    assert [p.index for p in load_scene(path).polygons] == [0, 1, 2]


@pytest.mark.parametrize("vertices", [
    "[[0,0,0],[4,0,0],[2,1,0],[4,4,0],[0,4,0]]",          # concave
    "[[0,0,0],[4,0,1],[4,4,2],[0,4,1]]",                   # tilted plane
    "[[-5,-5,0],[40,-5,0],[40,40,0]]",                     # reaching beyond the image
    "[[0,0,0],[0,4,0],[4,4,0],[4,0,0]]",                   # the other winding
])
def test_valid_polygons_are_accepted(tmp_path, vertices):
    path = tmp_path / "ok.toml"
    path.write_text(IMAGE + f"\n[[polygons]]\ncolor = [1, 0, 0]\nvertices = {vertices}\n")
    (polygon,) = load_scene(path).polygons
    assert np.isfinite(polygon.plane).all()


# --- the command line -----------------------------------------------------------------


@pytest.fixture
def existing_output(tmp_path):
    out = tmp_path / "out.npy"
    np.save(out, np.full((2, 2, 3), 0.25))
    return out, out.read_bytes(), out.stat().st_mtime_ns


def test_render_refuses_every_bad_scene_and_keeps_the_output(bad_scene, existing_output, capsys):
    path, index, rule = bad_scene
    out, before, mtime = existing_output
    assert main(["render", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert rule in err and str(path) in err and "Traceback" not in err
    assert out.read_bytes() == before and out.stat().st_mtime_ns == mtime
    assert sorted(p.name for p in out.parent.iterdir()) == sorted([out.name, path.name])


def test_render_process_exits_with_code_2_and_keeps_the_output(tmp_path, existing_output):
    out, before, _ = existing_output
    bad = tmp_path / "bow tie.toml"
    bad.write_text(with_bad_polygon("color = [1, 0, 0]\nvertices = [[0,0,0],[4,4,0],[4,0,0],[0,6,0]]"))
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, PYTHONPATH=str(root) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-m", "aaeval", "render", str(bad), "-o", str(out)],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120)
    assert done.returncode == 2, done.stderr
    assert f"{bad}: polygons[2]: polygon is self-crossing" in done.stderr
    assert "Traceback" not in done.stderr
    assert out.read_bytes() == before


def test_polygon_seen_edge_on_is_accepted_and_covers_nothing():
    from aaeval.renderers import render
    from aaeval.scenes import parse_scene

    scene = parse_scene({"image": {"width": 4, "height": 4}, "polygons": [
        {"color": [1, 0, 0], "vertices": [[0, 0, 0], [3, 3, 0], [3, 3, 2], [0, 0, 2]]}]})
    assert not render(scene, "catmull").any()
