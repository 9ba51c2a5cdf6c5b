"""The Python API: ``aaeval.load_scene``, ``render``, ``compare``,
``sweep``, ``open_sweep``, and Scene display in notebooks.

``compare`` is checked against an independent route: the ``aaeval compare`` command in a
subprocess (its JSON), and ``rmse`` recomputed here with numpy from two renders.
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import aaeval
from tests.helpers.sweep_util import write_config

ROOT = Path(__file__).resolve().parents[2]
FAN = ROOT / "configs" / "scenes" / "fan.toml"
SQUARE = {"image": {"width": 8, "height": 6, "background": [0.0, 0.0, 0.0]},
          "polygons": [{"color": [1.0, 0.5, 0.25], "vertices": [[1.5, 1.0, 0], [6.25, 1.0, 0], [6.25, 4.5, 0]]}]}


def test_import_aaeval_loads_no_renderer():
    code = "import sys, aaeval; print(any(m.startswith('aaeval.renderers') for m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.stdout.strip() == "False", done.stderr
    assert callable(aaeval.compare) and "compare" in dir(aaeval)
    with pytest.raises(AttributeError):
        aaeval.no_such_function  # noqa: B018


def test_load_scene_from_a_path_and_from_a_document():
    from_file = aaeval.load_scene(FAN)
    assert (from_file.width, from_file.height, len(from_file.polygons)) == (32, 32, 24)
    assert aaeval.load_scene(from_file) is from_file
    doc = aaeval.load_scene(SQUARE)
    assert doc.shape == (6, 8, 3)


def test_render_is_the_registry_render_and_conserves_area():
    from aaeval.renderers import render

    scene = aaeval.load_scene(SQUARE)
    image = aaeval.render(scene, "catmull")
    assert image.shape == (6, 8, 3)
    np.testing.assert_array_equal(image, render(scene, "catmull", frame=0))
    # exact box filter: the red channel sums to the triangle's area (4.75 * 3.5 / 2)
    assert image[..., 0].sum() == pytest.approx(4.75 * 3.5 / 2, rel=1e-12)


def test_compare_gives_the_numbers_of_the_command_line(tmp_path):
    methods = ["point", "supersample:k=4"]
    table = aaeval.compare(FAN, methods, reference="catmull", metrics=["rmse", "edge_rmse"], temporal=[])
    assert list(table["method"]) == ["point", "supersample"] and list(table["frame"]) == [0, 0]
    assert table["error"].isna().all() and np.isfinite(table["edge_rmse"]).all()  # the mask was built
    assert "<table" in table._repr_html_()
    out = tmp_path / "fan.json"
    args = [a for m in methods for a in ("-m", m)]
    done = subprocess.run([sys.executable, "-m", "aaeval", "compare", str(FAN), *args, "-r", "catmull", "--metric",
                           "rmse", "--metric", "edge_rmse", "--temporal", "sum_variation", "-q", "--json", str(out)],
                          capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0, done.stderr
    cli = {row["method"]: row for row in json.loads(out.read_text())["rows"]}
    for row in table.itertuples():
        assert row.rmse == cli[row.method]["rmse"] and row.edge_rmse == cli[row.method]["edge_rmse"]
    # and against numpy, from two renders
    scene = aaeval.load_scene(FAN)
    diff = aaeval.render(scene, "point") - aaeval.render(scene, "catmull")
    assert table["rmse"][0] == pytest.approx(np.sqrt(np.mean(diff ** 2)), rel=1e-12)


def test_compare_frames_give_a_row_per_method_and_frame():
    table = aaeval.compare({**SQUARE, "animation": {"frames": 3, "translate": [0.25, 0.0]}}, "point",
                           frames="all", metrics=["rmse"])
    assert list(table["frame"]) == [0, 1, 2] and (table["rmse"] > 0).all()
    assert table.attrs["document"]["summary"][0]["method"] == "point"


def test_scene_displays_and_has_a_short_repr():
    scene = aaeval.load_scene(FAN)
    assert len(repr(scene)) < 300 and "24 polygons" in repr(scene)
    long = aaeval.load_scene({**SQUARE, "polygons": SQUARE["polygons"] * 200})
    assert len(repr(long)) < 300
    picture = Image.open(io.BytesIO(_notebook_png(scene)))
    assert picture.size == (256, 256) and picture.mode == "RGB"  # 32 x 32 enlarged 8x
    pixels = np.asarray(picture)
    assert (pixels[::8, ::8] == pixels[7::8, 7::8]).all()  # nearest neighbour: each pixel a square


def test_show_draws_a_scene_or_an_image_at_the_size_asked():
    scene = aaeval.load_scene(SQUARE)
    image = aaeval.render(scene, "point")
    shown = Image.open(io.BytesIO(aaeval.show(image, size=512)._repr_png_()))
    assert shown.size == (512, 384)  # 8 x 6 enlarged 64x
    np.testing.assert_array_equal(np.asarray(shown)[::16, ::16], np.asarray(Image.open(io.BytesIO(
        aaeval.show(image, size=32)._repr_png_()))))  # the same pixels, each 16x larger
    assert Image.open(io.BytesIO(aaeval.show(scene)._repr_png_())).size == (256, 192)
    for bad in (0, 2.5, "big", 10**6):
        with pytest.raises(ValueError, match="size must be a whole number"):
            aaeval.show(image, size=bad)
    with pytest.raises(ValueError, match="a Scene or an"):
        aaeval.show(np.zeros((4, 4)))


NOTEBOOK_CELLS = [
    "import aaeval",
    "scene = aaeval.load_scene({'image': {'width': 32, 'height': 24}, 'polygons': [{'color': [1, 0.5, 0], "
    "'vertices': [[2.5, 2.5, 0], [28.3, 4.1, 0], [9.7, 21.2, 0]]}]})\nscene",
    "aaeval.show(aaeval.render(scene, 'point'), size=640)",
]


@pytest.mark.slow
def test_a_scene_in_jupyter_shows_at_a_readable_size(tmp_path):
    import base64

    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in NOTEBOOK_CELLS])
    NotebookClient(notebook, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    sizes = []
    for cell in notebook.cells[1:]:
        png = next(o["data"]["image/png"] for o in cell.outputs if "image/png" in o.get("data", {}))
        sizes.append(Image.open(io.BytesIO(base64.b64decode(png))).size)
    assert sizes == [(256, 192), (640, 480)]  # 32 x 24 enlarged 8x; 20x when asked for 640


def _notebook_png(scene) -> bytes:
    """What a notebook's PNG formatter draws for ``scene`` once the API lent it the preview."""
    from types import SimpleNamespace

    from IPython.core.formatters import PNGFormatter

    from aaeval.api import show_scenes_in

    formatter = PNGFormatter()
    assert formatter(scene) is None  # a Scene draws nothing by itself
    show_scenes_in(SimpleNamespace(display_formatter=SimpleNamespace(formatters={"image/png": formatter})))
    return formatter(scene)


@pytest.mark.slow
def test_sweep_then_open_sweep(tmp_path):
    config = write_config(tmp_path)
    folder = aaeval.sweep(config, tmp_path / "out", workers=1)
    assert (folder / "results.parquet").is_file()
    opened = aaeval.open_sweep(folder)
    assert len(opened.results) == 3 + 3 + 3 and opened.results["error"].isna().all()
    assert len(opened.temporal) >= 2 and len(repr(opened)) < 300
    again = aaeval.sweep(config, tmp_path / "out", workers=1)  # nothing left to run: the same table
    assert aaeval.open_sweep(again).results.equals(opened.results)
    with pytest.raises(FileNotFoundError):
        aaeval.open_sweep(tmp_path)


# Wrong arguments: the API's own error (a TypeError and a ValueError), one line naming the
# argument, raised before any file is read or anything rendered.
WRONG = [
    ("scene", lambda: aaeval.render(np.zeros((4, 4, 3)))),
    ("scene", lambda: aaeval.render(None)),
    ("scene", lambda: aaeval.load_scene(b"configs/scenes/fan.toml")),
    ("scene", lambda: aaeval.load_scene(3)),
    ("scene", lambda: aaeval.load_scene("fan\0.toml")),
    ("spec", lambda: aaeval.render(SQUARE, 3)),
    ("spec", lambda: aaeval.render(SQUARE, ["catmull"])),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame="1")),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame=None)),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame=True)),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame=0.0)),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame=-1)),
    ("frame", lambda: aaeval.render(SQUARE, "catmull", frame=1)),  # a still scene has frame 0 only
    ("specs", lambda: aaeval.compare(SQUARE, 3)),
    ("specs[1]", lambda: aaeval.compare(SQUARE, ["point", None])),
    ("reference", lambda: aaeval.compare(SQUARE, "point", reference=np.zeros(3))),
    ("frames", lambda: aaeval.compare(SQUARE, "point", frames=2.5)),
    ("frames", lambda: aaeval.compare(SQUARE, "point", frames=True)),
    ("frames", lambda: aaeval.compare(SQUARE, "point", frames="1")),
    ("metrics[0]", lambda: aaeval.compare(SQUARE, "point", metrics=[["rmse"]])),
    ("metrics", lambda: aaeval.compare(SQUARE, "point", metrics=3)),
    ("temporal", lambda: aaeval.compare(SQUARE, "point", temporal=b"flicker")),
    ("repeats", lambda: aaeval.compare(SQUARE, "point", repeats=0)),
    ("repeats", lambda: aaeval.compare(SQUARE, "point", repeats=2.0)),
    ("config", lambda: aaeval.sweep(None, "out")),
    ("config", lambda: aaeval.sweep(np.zeros(2), "out")),
    ("out", lambda: aaeval.sweep("exp.toml", None)),
    ("out", lambda: aaeval.sweep("exp.toml", b"out")),
    ("out", lambda: aaeval.sweep("exp.toml", "")),
    ("workers", lambda: aaeval.sweep("exp.toml", "out", workers=0)),
    ("workers", lambda: aaeval.sweep("exp.toml", "out", workers=-1)),
    ("workers", lambda: aaeval.sweep("exp.toml", "out", workers=1.5)),
    ("workers", lambda: aaeval.sweep("exp.toml", "out", workers=True)),
    ("workers", lambda: aaeval.sweep("exp.toml", "out", workers="2")),
    ("quiet", lambda: aaeval.sweep("exp.toml", "out", quiet="no")),
    ("cache_dir", lambda: aaeval.sweep("exp.toml", "out", cache_dir=3)),
    ("scheduler", lambda: aaeval.sweep("exp.toml", "out", scheduler="")),
    ("scheduler", lambda: aaeval.sweep("exp.toml", "out", scheduler=8786)),
    ("sweep(): unknown option", lambda: aaeval.sweep("exp.toml", "out", wrokers=2)),
    ("folder", lambda: aaeval.open_sweep(None)),
]


@pytest.mark.parametrize("name, call", WRONG, ids=[f"{i}-{n}" for i, (n, _) in enumerate(WRONG)])
def test_a_wrong_argument_is_refused_in_one_line_naming_it(name, call, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # nothing may be written: the folder stays empty
    with pytest.raises(aaeval.ArgumentError) as caught:
        call()
    message = str(caught.value)
    assert isinstance(caught.value, TypeError) and isinstance(caught.value, ValueError)
    assert "\n" not in message and len(message) < 300
    assert message.startswith(name.split("[")[0]) or name in message, message
    assert not list(tmp_path.iterdir())


def test_right_arguments_of_other_kinds_are_taken():
    scene = aaeval.load_scene(Path(FAN))
    assert aaeval.render(scene, "point", frame=np.int64(0)).shape == (32, 32, 3)
    table = aaeval.compare(SQUARE, ("point",), metrics="rmse", temporal=[], frames=np.int32(1))
    assert list(table["method"]) == ["point"] and table["rmse"].iloc[0] > 0


@pytest.mark.slow
def test_a_sweep_script_without_a_main_guard_raises_and_says_why(tmp_path):
    """Each local worker imports the script that started the sweep: without an
    ``if __name__ == "__main__":`` guard it runs the sweep again. The workers stop at once with
    the reason in one line each; sweep() raises SweepIncomplete naming the guard."""
    config = write_config(tmp_path)
    script = tmp_path / "run.py"
    script.write_text(f"import aaeval\naaeval.sweep({str(config)!r}, {str(tmp_path / 'out')!r}, workers=2)\n")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path,
                          env={**os.environ, "PYTHONPATH": str(ROOT), "AAEVAL_CACHE_DIR": str(tmp_path / "cache")})
    assert done.returncode == 1
    last = done.stderr.strip().splitlines()[-1]
    assert last.startswith("aaeval.api.SweepIncomplete:") and "9 of 9 cell(s) did not run" in last, done.stderr
    assert "if __name__ == \"__main__\":" in last
    workers = [line for line in done.stderr.splitlines() if line.startswith("aaeval.sweep() called while a worker")]
    assert 1 <= len(workers) <= 2 and done.stderr.count("Traceback") == 1  # the script's own, for the raise
    assert not (tmp_path / "out" / "cells").exists() or not list((tmp_path / "out" / "cells").iterdir())
