"""A Dask cluster started as one is started across machines (docs/distributed.md, "On several
machines"), here on one host: a `dask scheduler` process and a `dask worker` process running two
workers named host-0 and host-1, both from the command line, and `blurlab sweep --scheduler` in a
third process. The sweep's rows must equal the same sweep run in this process, bit for bit but
for the pass times, and both workers must have returned rows (the sweep's progress bar says how
many each).

Every process runs in a process group of its own that is killed at the end, or when a step does
not finish in time, so a stuck cluster fails the test instead of hanging the suite.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import pandas as pd
import pytest
from conftest import CLI_DEVICE
from method_picks import EXAMPLE, pick
from process_group import START_TIMEOUT_S, start_dask_cluster, stop_group

import blurlab as bl

pytest.importorskip("distributed")

SCENES = ["fan", "teapot_pass"]
# A tile filter with k and a gather with taps.
GRID = {EXAMPLE: {"k": [8, 16]}, pick(kind="gather", params=("taps",)): {"taps": [4]}}
SIZE = (64, 36)
REFERENCE_SAMPLES = 16
SWEEP_TIMEOUT_S = 300


@pytest.fixture(scope="module")
def command_line_cluster(tmp_path_factory):
    """(scheduler address, folder, the workers' names) of a scheduler and two workers started
    as separate processes from the command line, on llvmpipe where there is one (else the GPU)."""
    from distributed import Client

    folder = tmp_path_factory.mktemp("cli_cluster")
    env = {**os.environ, "BLURLAB_DEVICE": CLI_DEVICE}
    processes = []
    try:
        address = start_dask_cluster(folder, env, processes)
        with Client(address, timeout=START_TIMEOUT_S) as client:
            client.wait_for_workers(2, timeout=START_TIMEOUT_S)
            names = sorted(w["name"] for w in client.scheduler_info()["workers"].values())
        yield address, folder, names
    finally:
        for process in reversed(processes):
            stop_group(process)


def _without_timings(table: pd.DataFrame) -> pd.DataFrame:
    columns = [c for c in table.columns if not c.startswith("ms_") and c != "total_ms"]
    return table[columns].sort_values(["scene", "method", "params"]).reset_index(drop=True)


def test_a_command_line_cluster_sweeps_the_rows_of_a_local_sweep(command_line_cluster):
    address, folder, names = command_line_cluster
    assert names == ["host-0", "host-1"]
    config = folder / "sweep.toml"
    methods = "".join(
        f"[methods.{method}]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in grid.items())
        for method, grid in GRID.items()
    )
    config.write_text(
        f"scenes = {json.dumps(SCENES)}\nsize = {json.dumps(list(SIZE))}\n"
        f'reference_samples = {REFERENCE_SAMPLES}\nmetrics = ["psnr", "ssim"]\n'
        f'out = "{(folder / "cluster.csv").as_posix()}"\n{methods}'
    )
    sweep = subprocess.run(
        [sys.executable, "-m", "blurlab", "sweep", str(config), "--scheduler", address],
        capture_output=True,
        text=True,
        timeout=SWEEP_TIMEOUT_S,
        env={**os.environ, "BLURLAB_DEVICE": CLI_DEVICE},
    )
    assert sweep.returncode == 0, (sweep.stdout + sweep.stderr)[-4000:]
    remote = pd.read_csv(folder / "cluster.csv")
    bl.sweep(
        bl.Context(CLI_DEVICE),
        SCENES,
        GRID,
        SIZE,
        reference_samples=REFERENCE_SAMPLES,
        metrics=["psnr", "ssim"],
        out=folder / "local.csv",
        progress=False,
    )
    assert (
        len(remote) == len(SCENES) * 3
        and not remote.duplicated(["scene", "method", "params"]).any()
    )
    local = pd.read_csv(folder / "local.csv")
    assert sorted(remote.columns) == sorted(local.columns)
    pd.testing.assert_frame_equal(
        _without_timings(remote), _without_timings(local), check_exact=True, check_like=True
    )
    # Both workers took part: the sweep's progress bar ends with the rows each one returned.
    last = re.findall(r"rows_per_worker=([\w:,-]+)", sweep.stderr)[-1]
    rows = dict(item.split(":") for item in last.split(","))
    assert sorted(rows) == ["host-0", "host-1"], last
    assert sum(map(int, rows.values())) == len(remote)
    # Then where each worker's time went: a row per worker, their evaluations adding up.
    table = [line for line in sweep.stdout.splitlines() if line.startswith("| host-")]
    assert len(table) == 2, sweep.stdout[-4000:]
    assert sum(int(line.split("|")[4]) for line in table) == len(remote)
