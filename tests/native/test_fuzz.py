"""Fuzzing the command line: every case ends in an image or a one-line refusal (exit 2),
never a traceback, another exit code or a hang. The rules and generators are in
tests/helpers/fuzzing.py; scripts/fuzz_cli.py runs thousands of cases offline."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings

from tests.helpers.fuzzing import (PLACES, SVG_HEAD, Case, _entity_bomb, _use_bomb, cli_case, fuzz_environment, run_case,
                     toml_document, warm_up)

ROOT = Path(__file__).resolve().parents[2]
BOUND_S = 20.0  # per case, generous for a loaded 2-core CI machine; most take milliseconds


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fuzz")
    saved = {k: os.environ.get(k) for k in fuzz_environment()}
    os.environ.update(fuzz_environment())
    warm_up(folder)
    yield folder
    for k, v in saved.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.mark.slow
@settings(max_examples=300, deadline=None, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])
@given(case=cli_case(max_vertices=400))
def test_every_cli_case_ends_in_an_image_or_a_one_line_refusal(fuzz_dir, case):
    outcome = run_case(case, fuzz_dir / "case", BOUND_S)
    event(f"{case.kind}: {outcome.verdict}")  # --hypothesis-show-statistics: what the cases reached
    assert outcome.ok, (outcome.verdict, outcome.code, outcome.stderr[-2000:], case.args, case.kind,
                        case.scene[:300])


HOSTILE = {
    "binary": b"\x00\xff\xfe\x89PNG\r\n",
    "nan vertex": toml_document({"image": {"width": 4, "height": 4},
                                 "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [float("nan"), 1, 0], [1, 0, 0]]}]}).encode(),
    "huge image": toml_document({"image": {"width": 16384, "height": 16384},
                                 "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [3, 1, 0], [1, 3, 0]]}]}).encode(),
    "bow tie": toml_document({"image": {"width": 4, "height": 4},
                              "polygons": [{"color": [1, 0, 0], "vertices": [[0, 0, 0], [4, 4, 0], [4, 0, 0], [0, 4, 0]]}]}).encode(),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_a_real_process_refuses_hostile_files_in_one_line(tmp_path, name):
    scene = tmp_path / "scene.toml"
    scene.write_bytes(HOSTILE[name])
    env = {**os.environ, **fuzz_environment(), "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-m", "aaeval", "render", str(scene), "-m", "supersample:k=4", "-o",
                           str(tmp_path / "x.npy")], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("aaeval render: error: "), done.stderr
    assert str(scene) in done.stderr and not (tmp_path / "x.npy").exists()


VALID = toml_document({"image": {"width": 12, "height": 12}, "polygons": [
    {"color": [1.0, 0.5, 0.0], "vertices": [[1.5, 1.0, 1.0], [10.5, 2.0, 1.0], [3.0, 10.5, 1.0]]}]}).encode()
SVG_SCENE = toml_document({"image": {"width": 24, "height": 24, "background": [1.0, 1.0, 1.0]},
                           "svg": {"file": "src.svg", "scale": 1.0, "tolerance": 0.0625, "ignored": []},
                           "polygons": [{"color": [0.0, 0.0, 0.0],
                                         "vertices": [[1.0, 1.0, 1.0], [5.0, 1.0, 1.0], [5.0, 5.0, 1.0]]}]}).encode()
BILLION = VALID.replace(b'"polygons"', b'"animation" = {"frames" = 1000000000, "translate" = [0.0, 0.0]}\n"polygons"')
SVGS = {
    "use bomb": _use_bomb(11), "entity bomb": _entity_bomb(), "not xml": "not <svg", "empty": "",
    "nan": SVG_HEAD + '<path d="M1 1 L NaN 4 L 8 2 Z"/><rect x="NaN" width="4" height="4"/></svg>',
    "huge path": SVG_HEAD + '<path d="M12 2 ' + " ".join(f"L{12 + (i % 7)} {2 + (i % 11)}" for i in range(100000))
    + ' Z"/></svg>',
    "image": SVG_HEAD + '<image href="secret.png" width="8" height="8"/></svg>',
}
CLASSES = (
    [(f"scene as {place}", Case("valid", VALID, ["render", "{scene}", "-m", "point", "-o", "{out}.npy"], place=place))
     for place in sorted(set(PLACES))]
    + [(f"svg source as {place}", Case("svg", SVG_SCENE, ["render", "{scene}", "-m", "resvg", "-o", "{out}.npy"],
                                       svg=SVG_HEAD.encode() + b'<rect width="4" height="4"/></svg>', svg_kind="rect",
                                       svg_place=place)) for place in sorted(set(PLACES))]
    + [(f"svg {name} under resvg", Case("svg", SVG_SCENE, ["render", "{scene}", "-m", "resvg", "-o", "{out}.npy"],
                                        svg=text.encode(), svg_kind=name)) for name, text in SVGS.items()]
    + [(f"svg {name} imported", Case("svg", SVG_SCENE, ["import", "svg", "{svg}", "-o", "{out}.toml"],
                                     svg=text.encode(), svg_kind=name)) for name, text in SVGS.items()]
    + [(f"billion frames {cmd[0]}", Case("huge-frames", BILLION, cmd)) for cmd in (
        ["invariance", "{scene}", "-m", "point", "--quiet"],
        ["compare", "{scene}", "-m", "point", "-r", "supersample:k=2", "--frames", "all", "--quiet", "--json",
         "{out}.json"])]
    + [(f"sweep folder {damage}", Case("valid", VALID, ["sweep", "{dir}/exp.toml", "--out", "{dir}/sweep",
                                                        "--workers", "1", "--quiet", "--cache", "{dir}/cache",
                                                        "#" + damage]))
       for damage in ("unknown-field", "link-lock", "link-cell", "fifo-cell", "link-quarantine", "link-manifest")]
)


@pytest.mark.slow
@pytest.mark.parametrize("name, case", CLASSES, ids=[name for name, _ in CLASSES])
def test_each_hostile_class_ends_in_an_image_or_a_refusal_touching_nothing_outside(fuzz_dir, name, case):
    """Each hostile class once (a scene or SVG source placed where it could reach outside, a
    hostile SVG feature, a billion frames, a damaged sweep folder), deterministically (the
    generated cases draw them too)."""
    outcome = run_case(case, fuzz_dir / "case", BOUND_S)
    assert outcome.ok, (outcome.verdict, outcome.code, outcome.stderr[-2000:])
