"""The work a sweep sends to its workers (:mod:`aaeval.sweeps.tasks`): a cell's error measured
against its reference as written here, a chunk answering as its cells would one by one, a
spec crossing as text, and cells that never answered or lost their reference recorded as
failed with every metric NaN."""

from __future__ import annotations

import math
import socket

import numpy as np
import pytest

from aaeval.renderers.spec import MethodSpec
from aaeval.sweeps import load_experiment, plan
from aaeval.sweeps.record import CellRecord, Failure
from aaeval.sweeps.runner import record_identity
from aaeval.sweeps.tasks import failed_record, run_cell, run_cells, run_reference, worker_spec
from tests.helpers.sweep_util import write_config

CONFIG = """
[experiment]
name = "tasks"
reference = "catmull"
metrics = ["rmse", "psnr"]
temporal = []

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 2, size = 12}]
methods = ["point", "supersample:k=2"]
"""


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    return plan(load_experiment(write_config(tmp_path_factory.mktemp("tasks"), CONFIG)))


def _reference(p) -> dict:
    src = p.cell.scene_source
    return run_reference(src.document, src.source, p.cell.frame, str(p.cell.reference), False, src.digest)


def _payload(p, reference: dict, *, spec_as_text: bool = False) -> dict:
    """What the sweep sends for the planned cell ``p``, its reference rendered."""
    identity = record_identity(p, reference)
    if spec_as_text:  # as a Dask worker receives it: no method registered where it was unpickled
        identity = {**identity, "spec": str(identity["spec"]), "reference": str(identity["reference"])}
    src = p.cell.scene_source
    return {"identity": identity, "run": {"executor": "this process", "workers": 1}, "document": src.document,
            "source": src.source, "metrics": list(p.cell.metrics), "repeats": 2,
            "reference_image": reference.get("image"), "reference_error": reference.get("error")}


def test_a_cell_measures_its_image_against_its_reference(planned):
    for p in planned:
        reference = _reference(p)
        assert "error" not in reference and reference["host"] == socket.gethostname()
        record, image, flip = run_cell(_payload(p, reference))
        back = CellRecord.from_json(record)
        assert back.error is None and back.failure is None and back.key == p.key
        assert image.shape == reference["image"].shape and flip.shape == image.shape[:2]
        rmse = math.sqrt(float(np.mean((image - reference["image"]) ** 2)))  # written here, not through aaeval.metrics
        assert back.metrics["rmse"] == pytest.approx(rmse, rel=1e-12)
        assert back.metrics["rmse"] > 0  # neither point sampling nor 2x2 supersampling is exact
        assert back.repeats == 2 and back.render_s_min <= back.render_s <= back.render_s_max
        assert back.host == socket.gethostname() and back.executor == "this process"


def test_a_chunk_answers_as_its_cells_one_by_one_and_a_spec_may_cross_as_text(planned):
    payloads = [_payload(p, _reference(p)) for p in planned]
    together = run_cells(payloads)
    as_text = run_cells([_payload(p, _reference(p), spec_as_text=True) for p in planned])
    assert len(together) == len(planned)
    for payload, chunked, texted in zip(payloads, together, as_text):
        alone = run_cell(payload)
        for other in (chunked, texted):
            assert other[0]["key"] == alone[0]["key"] and other[0]["spec"] == alone[0]["spec"]
            assert other[0]["metrics"] == alone[0]["metrics"]
            np.testing.assert_array_equal(other[1], alone[1])
            np.testing.assert_array_equal(other[2], alone[2])
    assert worker_spec("supersample:k=2") == MethodSpec.parse("supersample:k=2")


@pytest.mark.parametrize("failure", [Failure.WORKER_DIED, Failure.TIMED_OUT])
def test_a_cell_that_never_answered_is_failed_with_every_metric_nan(planned, failure):
    p = planned[0]
    record = CellRecord.from_json(failed_record(_payload(p, {"image": None}), "worker died: signal 9", failure))
    assert record.failure == failure.value and record.error == "worker died: signal 9"
    assert set(record.metrics) == {"rmse", "psnr"} and all(math.isnan(v) for v in record.metrics.values())
    assert math.isnan(record.render_s) and record.repeats == 2 and record.key == p.key


def test_a_cell_whose_reference_failed_says_so_and_a_failing_reference_answers_its_error(planned):
    p = planned[0]
    record, image, _ = run_cell(_payload(p, {"error": "RuntimeError: out of memory"}))
    back = CellRecord.from_json(record)
    assert back.error.endswith(f"reference {p.cell.reference} failed: RuntimeError: out of memory")
    assert back.failure == Failure.REFERENCE.value and image is None
    assert all(math.isnan(v) for v in back.metrics.values())
    src = p.cell.scene_source
    answer = run_reference(src.document, src.source, 0, "no-such-method", False, src.digest)
    assert set(answer) == {"error", "host"} and "no-such-method" in answer["error"]
