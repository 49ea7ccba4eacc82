"""A command run in a process group of its own, killed whole if it does not finish in time, so
that a stuck cluster (Dask workers are processes too) fails its test instead of hanging the
suite."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def run_or_fail(command: list[str], timeout_s: float, what: str, cwd=None) -> str:
    """Runs `command`; returns its output (stdout and stderr together). Fails the test if it
    exits non-zero, or if it runs past `timeout_s` (then its whole group is killed)."""
    process = subprocess.Popen(
        command,
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:
        output, _ = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        output, _ = process.communicate()
        pytest.fail(f"{what} did not finish in {timeout_s} s:\n{output[-4000:]}")
    assert process.returncode == 0, output[-4000:]
    return output


START_TIMEOUT_S = 120  # how long a scheduler gets to write its file


def start_in_group(arguments: list[str], log: Path, env: dict) -> subprocess.Popen:
    """`python -m ARGUMENTS` in a process group of its own, its output to `log`."""
    with log.open("w") as out:
        return subprocess.Popen(
            [sys.executable, "-m", *arguments],
            stdout=out,
            stderr=subprocess.STDOUT,
            env=env,
            start_new_session=True,
        )


def stop_group(process: subprocess.Popen) -> None:
    """Ends start_in_group's process and its children: SIGTERM, then SIGKILL."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def wait_for_file(path: Path, process: subprocess.Popen, log: Path) -> None:
    """Waits for a scheduler's file; fails the test with its log if it never comes."""
    deadline = time.monotonic() + START_TIMEOUT_S
    while not path.exists() or not path.read_text().strip():
        if process.poll() is not None or time.monotonic() > deadline:
            pytest.fail(f"the scheduler did not start:\n{log.read_text()[-4000:]}")
        time.sleep(0.2)


def start_dask_cluster(folder: Path, env: dict, processes: list, options=()) -> str:
    """Starts, from the command line on 127.0.0.1, `dask scheduler` and a `dask worker`
    process of two one-thread workers named host-0 and host-1, both given `options` (with
    "--protocol tls" among them only the scheduler takes that one), each in a process group
    of its own appended to `processes` (stop them with stop_group). Returns the scheduler's
    address once its file is written."""
    scheduler_file, log = folder / "scheduler.json", folder / "scheduler.log"
    common = [
        "--host",
        "127.0.0.1",
        "--no-dashboard",
        "--dashboard-address",
        "127.0.0.1:0",
        *options,
    ]
    processes.append(
        start_in_group(
            ["dask", "scheduler", "--port", "0", "--scheduler-file", str(scheduler_file), *common],
            log,
            env,
        )
    )
    wait_for_file(scheduler_file, processes[-1], log)
    address = json.loads(scheduler_file.read_text())["address"]
    worker = [o for o in common if o not in ("--protocol", "tls")]
    processes.append(
        start_in_group(
            ["dask", "worker", address, "--nthreads", "1", "--nworkers", "2", "--name", "host"]
            + worker,
            folder / "worker.log",
            env,
        )
    )
    return address
