"""A command run in a process group of its own, killed whole if it does not finish in time, so
that a stuck cluster (Dask workers are processes too) fails its test instead of hanging the
suite."""

from __future__ import annotations

import os
import signal
import subprocess

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
