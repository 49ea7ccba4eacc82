"""benchmarks/sweep_scaling.py runs end to end on llvmpipe (tiny images): one and two workers,
new and warm clusters, give the same rows, and every worker's account adds up to the sweep's
evaluations. The benchmark runs in a process of its own, killed if it does not finish."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from conftest import CLI_DEVICE
from process_group import run_or_fail

pytest.importorskip("distributed")

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "sweep_scaling.py"
TIMEOUT_S = 300


@pytest.mark.parametrize("warm", [False, True], ids=["new", "warm"])
def test_sweep_scaling_gives_the_same_rows_and_accounts_for_each_worker(tmp_path, warm):
    record = tmp_path / "scaling.json"
    command = [
        sys.executable,
        str(SCRIPT),
        "--device",
        CLI_DEVICE,
        "--size",
        "48x27",
        "--scenes",
        "fan",
        "thin_bar",
        "--metrics",
        "psnr,ssim",
        "--reference-samples",
        "8",
        "--repeats",
        "1",
        "--workers",
        "1",
        "2",
        "--json",
        str(record),
    ] + (["--warm"] if warm else [])
    output = run_or_fail(command, TIMEOUT_S, "sweep_scaling.py", cwd=SCRIPT.parent)
    result = json.loads(record.read_text())
    assert [run["workers"] for run in result["runs"]] == [1, 2]
    for run in result["runs"]:
        assert run["same_rows_as_first"], run["name"]
        reports = run["workers_report"].values()
        assert len(reports) == run["workers"]
        assert sum(r["evaluations"] for r in reports) == result["evaluations"]
        for report in reports:
            assert report["busy_s"] + report["context_s"] <= run["wall_s"] + 1e-6
            # A warm cluster opened its contexts before the timed sweep.
            assert (report["context_s"] == 0) == warm or report["evaluations"] == 0
    assert "| worker | device | tasks (next waiting) |" in output
