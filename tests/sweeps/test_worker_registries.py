"""A sweep worker loads the registries (aaeval.registries.load) before its first task, so
the MethodSpec a task carries is parsed on arrival against every method, as in the sweep."""

from __future__ import annotations

import pytest

from aaeval.sweeps.local_workers import ProcessExecutor
from aaeval.renderers import MethodSpec


def spec_as_received(spec):
    """What the worker got: the spec's type, the method it names, whether it loaded."""
    from aaeval import registries

    return type(spec).__name__, getattr(getattr(spec, "method", None), "name", None), registries.loaded()


def test_a_local_worker_parses_the_spec_it_receives_against_loaded_registries():
    executor = ProcessExecutor(1)
    try:
        got = list(executor.run(spec_as_received, [(MethodSpec.parse("supersample:k=2"),)]))
    finally:
        executor.close()
    # unloaded, the spec would arrive as its text (the worker knowing no method)
    assert got == [(0, ("MethodSpec", "supersample", True), None)]


@pytest.mark.slow
def test_a_dask_worker_process_loads_the_registries_when_it_joins():
    import distributed

    from aaeval.sweeps.dask_executor import DaskExecutor

    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, protocol="tcp",
                                  dashboard_address=":0") as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            got = list(executor.run(spec_as_received, [(MethodSpec.parse("supersample:k=2"),)]))
        finally:
            executor.close()
    assert got == [(0, ("MethodSpec", "supersample", True), None)]
