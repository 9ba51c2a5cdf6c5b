"""The same sweep on a Dask distributed cluster (a real LocalCluster on loopback)."""

from __future__ import annotations

import pandas as pd
import pytest

from aaeval.sweeps import SweepStore, load_experiment, run_sweep
from tests.helpers.sweep_util import write_config

import distributed


@pytest.fixture(scope="module")
def cluster():
    # threads in this process keep the test quick; the scheduler still talks TCP on loopback
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp",
                                  host="127.0.0.1", dashboard_address=":0") as c:
        yield c


@pytest.mark.slow
def test_sweep_on_a_local_cluster_matches_the_local_run(tmp_path, cluster):
    assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
    exp = load_experiment(write_config(tmp_path))
    summary = run_sweep(exp, tmp_path / "dask", scheduler=cluster.scheduler_address, quiet=True,
                        cache_dir=tmp_path / "cache-dask")
    assert summary.ran == 9 and not summary.lost and summary.executor.startswith("Dask cluster tcp://127.0.0.1")
    local = run_sweep(exp, tmp_path / "local", workers=1, quiet=True, cache_dir=tmp_path / "cache-local")
    assert local.ran == 9
    a = pd.read_parquet(tmp_path / "dask" / "results.parquet").sort_values("key").reset_index(drop=True)
    b = pd.read_parquet(tmp_path / "local" / "results.parquet").sort_values("key").reset_index(drop=True)
    assert list(a["key"]) == list(b["key"])
    pd.testing.assert_series_equal(a["rmse"], b["rmse"])
    assert a["error"].isna().all()
    assert (a["executor"].str.startswith("Dask cluster")).all()
    # and a rerun through the cluster finds everything done
    again = run_sweep(exp, tmp_path / "dask", scheduler=cluster.scheduler_address, quiet=True,
                      cache_dir=tmp_path / "cache-dask")
    assert again.skipped == 9 and again.ran == 0
    assert len(SweepStore(tmp_path / "dask").finished()) == 9
