"""Fuzzing the command line: every case ends in an image or a one-line refusal (exit 2),
never a traceback, another exit code or a hang. The rules and generators are in
tests/fuzzing.py; scripts/fuzz_cli.py runs thousands of cases offline."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings

from fuzzing import Case, cli_case, fuzz_environment, run_case, toml_document, warm_up

ROOT = Path(__file__).resolve().parents[1]
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
