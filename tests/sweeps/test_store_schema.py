"""A sweep folder validated on read: every field of a cell checked against
the record's schema, a cell that fails quarantined with its reason (so the folder is never
blocked) and run again; stored images checked against the record's size and dtype before
they are read (a sparse 21 GB file is refused from its header); a manifest of the wrong
shape refused in one line; the report and the table run on what is left."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore
from tests.helpers.sweep_util import run_small_sweep

TAMPER = {
    "string frame": ("frame", "0"),
    "integer group": ("group", 7),
    "list spec": ("spec", ["catmull"]),
    "string options": ("options", "spp=4"),
    "nested options": ("options", {"a": {"b": 1}}),
    "float width": ("width", 12.5),
    "bool repeats": ("repeats", True),
    "infinite render time": ("render_s", float("inf")),
    "metric text": ("metrics", {"rmse": "0.1"}),
    "list kind": ("reference_kind", ["exact"]),
    "huge size": ("width", 1 << 30),
    "negative frame": ("frame", -1),
    "another frame": ("frame", 7),  # reads well, but is not this key's cell: it blocked the folder
    "another group": ("group", "stability"),
}


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    base = tmp_path_factory.mktemp("finished")
    run_small_sweep(base)
    return base


def _copy(finished, tmp_path):
    import shutil

    shutil.copytree(finished / "out", tmp_path / "out")
    shutil.copy(finished / "exp.toml", tmp_path / "exp.toml")
    shutil.copytree(finished / "cache", tmp_path / "cache")
    return tmp_path / "out"


def _a_cell(out, unlike=None):
    """A finished cell (whose ``field`` is not already ``value``, for ``unlike=(field, value)``:
    cell files are named by a key that moves with the code's version, so the first one can
    be a cell the tampering would leave as it was)."""
    for path in sorted((out / "cells").glob("*.json")):
        record = json.loads(path.read_text())
        if record["error"] is None and (unlike is None or json.dumps(record.get(unlike[0])) != json.dumps(unlike[1])):
            return path, record
    raise AssertionError("no finished cell")


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(TAMPER))
def test_a_cell_of_the_wrong_types_is_quarantined_with_its_reason_and_run_again(finished, tmp_path, capsys, case):
    out = _copy(finished, tmp_path)
    field, value = TAMPER[case]
    path, record = _a_cell(out, unlike=(field, value))
    record[field] = value
    path.write_text(json.dumps(record))
    capsys.readouterr()
    again = run_small_sweep(tmp_path)
    err = capsys.readouterr().err
    assert str(path) in err and (repr(field) in err or field in err), err
    assert again.ran == 1 and not again.lost
    assert len(SweepStore(out).finished()) == 9
    assert len(pd.read_parquet(out / "results.parquet")) == 9


@pytest.mark.slow
def test_the_report_runs_on_a_folder_whose_damaged_cell_was_run_again(finished, tmp_path, capsys):
    # once, not per damage: what the report reads is the table the rerun wrote, the same for all
    out = _copy(finished, tmp_path)
    path, record = _a_cell(out)
    record["frame"] = "0"
    path.write_text(json.dumps(record))
    assert run_small_sweep(tmp_path).ran == 1
    # PNG only: the report reads the same tables and draws the same figures; SVG and PDF are
    # the same figures saved again, whatever the folder held
    assert main(["report", str(out), "--png-only"]) == 0


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["complex", "wrong shape", "sparse huge"])
def test_an_image_unlike_its_record_is_refused_before_it_is_read(finished, tmp_path, capsys, damage):
    out = _copy(finished, tmp_path)
    path, record = _a_cell(out)
    image = out / "images" / f"{path.stem}.npy"
    h, w = record["height"], record["width"]
    if damage == "complex":
        np.save(image, np.zeros((h, w, 3), dtype=complex))
    elif damage == "wrong shape":
        np.save(image, np.zeros((h + 1, w, 3)))
    else:  # a header that matches the file's size, claiming 21 GB: never read whole
        with open(image, "wb") as f:
            np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False,
                                                     "shape": (50_000, 50_000, 1)})
            f.truncate(f.tell() + 50_000 * 50_000 * 8)
    capsys.readouterr()
    again = run_small_sweep(tmp_path)
    err = capsys.readouterr().err
    assert str(image) in err, err
    assert again.ran == 1 and len(SweepStore(out).finished()) == 9


@pytest.mark.parametrize("damage", ["no experiment", "metrics text", "cells of numbers", "fail_above nan"])
def test_a_manifest_of_the_wrong_shape_is_refused_in_one_line(finished, tmp_path, capsys, damage):
    out = _copy(finished, tmp_path)
    manifest = json.loads((out / "manifest.json").read_text())
    if damage == "no experiment":
        del manifest["experiment"]
    elif damage == "metrics text":
        manifest["metrics"] = "rmse"
    elif damage == "cells of numbers":
        manifest["cells"] = [1, 2, 3]
    else:
        manifest["fail_above"] = float("nan")
    (out / "manifest.json").write_text(json.dumps(manifest))
    capsys.readouterr()
    code = main(["report", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    assert "manifest.json" in err and "not a sweep manifest" in err, err
