"""Sweeps on a Dask cluster: the same rows as one worker and as a local sweep, resuming from the
same CSV file, each worker's device, and bad arguments.

The cluster runs in tests/cluster_job.py, in a process group of its own that is killed if it
does not finish in time, so a stuck cluster fails the test instead of hanging the suite.
"""

from __future__ import annotations

import json
import sys
import types
from pathlib import Path

import pandas as pd
import pytest
from method_picks import pick
from process_group import run_or_fail

import blurlab as bl
from blurlab.studies import cluster, cluster_devices

pytest.importorskip("distributed")

JOB = Path(__file__).parent / "cluster_job.py"
TIMEOUT_S = 300
GATHER = pick(kind="gather", params=("taps",))  # any method: the arguments are refused first


@pytest.fixture(scope="module")
def job(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("cluster")
    run_or_fail([sys.executable, str(JOB), str(folder)], TIMEOUT_S, "the cluster sweep")
    return folder


def _without_timings(table: pd.DataFrame, also=()) -> pd.DataFrame:
    columns = [c for c in table.columns if not c.startswith("ms_") and c not in ("total_ms", *also)]
    return table[columns].sort_values(["scene", "method", "params"]).reset_index(drop=True)


def test_two_workers_give_the_rows_of_one_worker_and_of_a_local_sweep(job):
    one = pd.read_csv(job / "one.csv")
    two = pd.read_csv(job / "two.csv")
    local = pd.read_csv(job / "local.csv")
    assert len(one) == 2 * 5 and not one.duplicated(["scene", "method", "params"]).any()
    assert sorted(one.columns) == sorted(two.columns) == sorted(local.columns)
    # Every parameter, error and count, bit for bit; only the pass times may differ.
    pd.testing.assert_frame_equal(
        _without_timings(two), _without_timings(one), check_exact=True, check_like=True
    )
    pd.testing.assert_frame_equal(
        _without_timings(local), _without_timings(one), check_exact=True, check_like=True
    )
    assert two["total_ms"].gt(0).all()


def test_both_workers_evaluated_scenes(job):
    reports = json.loads((job / "workers.json").read_text())
    kept = {worker: report["scenes_kept"] for worker, report in reports.items()}
    assert len(kept) == 2
    assert all(kept.values()), kept  # each worker rendered at least one scene's reference
    assert set().union(*map(set, kept.values())) == {0, 1}


def test_worker_reports_account_for_every_evaluation_and_second(job):
    reports = list(json.loads((job / "workers.json").read_text()).values())
    # forget_scenes started each account anew after the one-worker sweep: 10 rows since.
    assert sum(r["evaluations"] for r in reports) == 10
    # The second worker opened its context in this sweep, the first one before it.
    assert sorted(r["context_s"] > 0 for r in reports) == [False, True]
    for report in reports:
        assert report["device"].startswith("EGL device")
        assert report["tasks"] >= 1
        # Each worker was given two chunks at once (CHUNKS_IN_FLIGHT): the second was on the
        # worker when the first ended.
        assert report["next_chunk_waiting"] >= 1
        assert report["references_s"] > 0 and report["g_buffers_s"] > 0
        assert report["warm_up_s"] > 0 and report["evaluations_s"] > 0
        # evaluations_s is what the other phases leave of the busy time.
        assert all(report[f"{phase}_s"] >= 0 for phase in cluster.ACCOUNT)


def test_a_cluster_sweeps_table_says_where_each_workers_time_went(job):
    """table.attrs["workers"]: each worker's account of that sweep alone, which the reports
    taken after it (started anew just before it) agree with."""
    accounts = json.loads((job / "two_accounts.json").read_text())
    reports = json.loads((job / "workers.json").read_text())
    assert sorted(accounts) == ["0", "1"]  # LocalCluster's worker names
    assert sum(a["evaluations"] for a in accounts.values()) == 10
    # Every batch of GPU metrics a worker read came back with its tickets (docs/spec.md §6.3).
    assert [a["stale_readbacks"] for a in accounts.values()] == [0, 0]
    # The reports are keyed by address, the accounts by name: compared as sorted lists.
    assert sorted(a["busy_s"] for a in accounts.values()) == pytest.approx(
        sorted(r["busy_s"] for r in reports.values())
    )
    assert sorted(a["evaluations"] for a in accounts.values()) == sorted(
        r["evaluations"] for r in reports.values()
    )
    table = cluster.account_table(accounts, 100.0)
    assert table.count("| EGL device") == 2 and "not on any worker's account" in table


def test_a_helper_renders_a_scene_again_only_where_it_pays():
    # 10 evaluations of 0.5 s left: 5 s alone, against a setup of 2 s to help.
    assert cluster.worth_helping(10, 0.5, 2.0)
    assert not cluster.worth_helping(10, 0.5, 2.5)  # 5 s is not more than twice 2.5 s
    assert not cluster.worth_helping(1, 0.5, 0.3)
    # No estimate yet: wait for the first chunk, then import its references.
    assert not cluster.worth_helping(100, None, 1.0)
    assert not cluster.worth_helping(100, 0.5, None)


def test_a_helper_imports_the_scene_instead_of_rendering_it(job):
    """One scene, two workers, one configuration a chunk: the second worker waits for the
    first chunk, then helps with references it imported, and the rows are a local sweep's."""
    helped = pd.read_csv(job / "helped.csv")
    local = pd.read_csv(job / "local.csv")
    local = local[local["scene"] == "fan"]
    pd.testing.assert_frame_equal(
        _without_timings(helped), _without_timings(local), check_exact=True, check_like=True
    )
    reports = list(json.loads((job / "helped_workers.json").read_text()).values())
    owner, helper = sorted(reports, key=lambda r: r["imports"])
    assert helper["imports"] >= 1 and helper["evaluations"] >= 1
    assert helper["references_s"] == 0  # it rendered no reference
    assert owner["exports"] >= 1 and owner["references_s"] > 0
    assert owner["evaluations"] + helper["evaluations"] == len(local)


def test_a_cluster_sweep_resumes_from_the_csv_file(job):
    saved = pd.read_csv(job / "resumed.csv")
    assert len(saved) == 10 and not saved.duplicated(["scene", "method", "params"]).any()
    assert saved["repeats"].tolist().count(3) == 1  # the row `blurlab sweep` made (repeats 3)
    table = pd.read_csv(job / "resumed_table.csv")
    expected = _without_timings(pd.read_csv(job / "one.csv"), ["repeats"])
    for got in (table, saved):
        pd.testing.assert_frame_equal(
            _without_timings(got, ["repeats"]), expected, check_exact=True, check_like=True
        )


def test_a_chunk_whose_context_the_gpu_reset_is_evaluated_again_on_a_new_one(job):
    resets = json.loads((job / "reset.json").read_text())
    assert sum(resets["workers"].values()) == resets["table"] >= 1
    again = pd.read_csv(job / "reset.csv")
    pd.testing.assert_frame_equal(
        _without_timings(again), _without_timings(pd.read_csv(job / "one.csv")), check_exact=True
    )


def test_worker_rank_comes_from_the_worker_name():
    assert cluster_devices.worker_rank(3) == 3
    assert cluster_devices.worker_rank("node7-1") == 1
    assert cluster_devices.worker_rank("12") == 12
    assert cluster_devices.worker_rank("tcp://10.0.0.1:4000") is None
    assert cluster_devices.worker_rank(None) is None


def test_worker_device_follows_blurlab_device_then_rank():
    assert cluster_devices.worker_device(5, {"BLURLAB_DEVICE": "software"}) == "software"
    assert cluster_devices.worker_device(5, {"BLURLAB_DEVICE": " 1 "}) == 1
    gpus = [d["index"] for d in bl.Context.devices() if d["kind"] == "gpu"]
    expected = gpus[3 % len(gpus)] if gpus else "software"
    assert cluster_devices.worker_device(3, {"BLURLAB_DEVICE": ""}) == expected
    with pytest.raises(ValueError, match="BLURLAB_DEVICE must be one of"):
        cluster_devices.worker_device(0, {"BLURLAB_DEVICE": "tpu"})


def test_blurlab_gpus_keeps_the_ranks_on_the_first_gpus():
    assert cluster_devices.gpu_share("", 4) == 4
    assert cluster_devices.gpu_share("0", 4) == 4
    assert cluster_devices.gpu_share(" 1 ", 4) == 1
    assert cluster_devices.gpu_share("8", 4) == 4  # no more than the machine has
    with pytest.raises(ValueError, match="BLURLAB_GPUS must be a GPU count"):
        cluster_devices.gpu_share("two", 4)
    gpus = [d["index"] for d in bl.Context.devices() if d["kind"] == "gpu"]
    expected = gpus[0] if gpus else "software"
    assert cluster_devices.worker_device(3, {"BLURLAB_DEVICE": "", "BLURLAB_GPUS": "1"}) == expected


def test_bad_cluster_arguments_are_rejected(ctx):
    with pytest.raises(ValueError, match="pass ctx=None"):
        bl.sweep(ctx, ["fan"], [GATHER], (64, 36), cluster="tcp://127.0.0.1:1")
    with pytest.raises(TypeError, match="or ctx=None and a cluster"):
        bl.sweep(None, ["fan"], [GATHER], (64, 36), progress=False)
    with pytest.raises(TypeError, match="cluster must be a distributed.Client"):
        bl.sweep(None, ["fan"], [GATHER], (64, 36), cluster=42, progress=False)
    with pytest.raises(ValueError, match="chunk_size"):
        bl.sweep(None, ["fan"], [GATHER], cluster="tcp://127.0.0.1:1", chunk_size=0)
    with pytest.raises(ValueError, match="n_workers"):
        bl.local_cluster(0)
    with pytest.raises(ValueError, match="device must be one of"):
        bl.local_cluster(1, device="tpu")
    with pytest.raises(ValueError, match="one thread each"):
        bl.local_cluster(1, threads_per_worker=2)
    with pytest.raises(ValueError, match="gpus must be None or an integer >= 1"):
        bl.local_cluster(1, gpus=0)


def test_chunks_waiting_counts_from_a_copy_of_the_workers_tasks(monkeypatch):
    # The worker's event loop changes its task dict while a chunk runs on the worker's thread;
    # a dict that changes as it is read stands for that here.
    class Changing(dict):
        def values(self):
            self["another"] = types.SimpleNamespace(key="run_chunk-9", state="ready")
            return super().values()

        def __iter__(self):
            self["another"] = types.SimpleNamespace(key="run_chunk-9", state="ready")
            return super().__iter__()

    tasks = Changing(
        {
            "a": types.SimpleNamespace(key="run_chunk-1", state="executing"),
            "b": types.SimpleNamespace(key="run_chunk-2", state="ready"),
            "c": types.SimpleNamespace(key="export-3", state="waiting"),
        }
    )
    worker = types.SimpleNamespace(state=types.SimpleNamespace(tasks=tasks))
    distributed = types.SimpleNamespace(get_worker=lambda: worker)
    monkeypatch.setattr(cluster, "require_distributed", lambda: distributed)
    assert cluster.chunks_waiting() == 1
