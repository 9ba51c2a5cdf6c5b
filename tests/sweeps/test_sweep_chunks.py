"""Cells go to workers in chunks: every cell once, chunks shrinking towards the end, and a
chunk whose worker died runs again cell by cell so the failure lands on the cell alone."""

from __future__ import annotations

import pytest

from aaeval.sweeps.task_failures import WorkerDied
from aaeval.sweeps.runner import _run_in_chunks, chunks
from aaeval.sweeps.tasks import run_cell, run_cells


@pytest.mark.parametrize("count, workers", [(0, 2), (1, 2), (7, 1), (960, 2), (3000, 2), (100, 16)])
def test_chunks_cover_every_cell_once_and_shrink_towards_the_end(count, workers):
    parts = chunks(count, workers, most=16)
    assert [i for part in parts for i in part] == list(range(count))
    sizes = [len(part) for part in parts]
    assert all(1 <= size <= 16 for size in sizes)
    assert sizes == sorted(sizes, reverse=True)
    assert not sizes or sizes[-1] == 1  # the last cells go one at a time: no long wait at the end


class _Dying:
    """An executor whose worker dies on any task holding the payload "bad"."""

    workers = 2

    def __init__(self):
        self.tasks = []

    def run(self, fn, payloads):
        for i, payload in enumerate(payloads):
            cells = payload[0] if fn is run_cells else [payload[0]]
            self.tasks.append((fn, cells))
            if "bad" in cells:
                yield i, None, WorkerDied("worker died: signal 11 (SIGSEGV)")
            else:
                results = [f"done {cell}" for cell in cells]
                yield i, results if fn is run_cells else results[0], None


def test_a_chunk_whose_worker_died_runs_again_one_cell_per_task():
    work = [(f"c{i}",) for i in range(200)]
    work[1] = ("bad",)  # in the first chunk, of 12 cells
    executor = _Dying()
    outcomes = list(_run_in_chunks(executor, work))
    done = {i: result for indices, results, exc in outcomes if exc is None for i, result in zip(indices, results)}
    died = [indices for indices, _, exc in outcomes if exc is not None]
    assert died == [(1,)]  # only the cell that killed its worker
    assert done == {i: f"done {work[i][0]}" for i in range(200) if i != 1}
    singles = [cells for fn, cells in executor.tasks if fn is run_cell]
    chunk_of_bad = next(cells for fn, cells in executor.tasks if fn is run_cells and "bad" in cells)
    assert len(chunk_of_bad) == 12
    assert sorted(c for (c,) in singles) == sorted(chunk_of_bad)  # its chunk-mates ran again, alone
