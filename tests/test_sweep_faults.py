"""A sweep's out-file survives faults (docs/reliability.md, "A store that survives faults"):
a sweep process killed (SIGKILL) at 20 points, some in the middle of writing a row, and rerun
each time, ends with every row exactly once and the numbers of an uninterrupted run; a sweep
on a cluster whose worker is killed completes with the same rows, bit for bit."""

from __future__ import annotations

import concurrent.futures
import json
import os
import random
import subprocess
import sys
from pathlib import Path

import pandas as pd
from process_group import run_or_fail

HERE = Path(__file__).parent
JOB = HERE / "sweep_kill_job.py"
KILLS = 20
CHAINS = 2  # files killed and rerun in turn, side by side (the machine has 2 cores)
# Everything of a row but its pass times, which are measured anew by each run.
EXACT = ["scene", "method", "params", "psnr", "ssim", "reference_samples", "identity"]


def run_job(out: Path, rows: int, cut: float | None = None) -> int:
    """The job's exit code: 0 finished, -9 (SIGKILL) killed at its kill point."""
    command = [sys.executable, str(JOB), str(out), str(rows)] + ([str(cut)] if cut else [])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode in (0, -9), done.stderr[-3000:]
    return done.returncode


def kill_points() -> list[tuple[int, float | None]]:
    """20 (rows appended before the kill, fraction of the killing row written or None)."""
    chosen = random.Random(20261127)
    return [
        (chosen.randint(1, 5), chosen.choice([None, round(chosen.uniform(0.05, 0.95), 2)]))
        for _ in range(KILLS)
    ]


def killed_and_rerun(folder: Path, points) -> list[Path]:
    """Runs the job into a file, killing it at each point in turn; a file whose run finished
    before its kill point is done and the next point starts a new one. Every file is then
    finished by one run without a kill. Returns the files."""
    files = [folder / "0.csv"]
    for rows, cut in points:
        if run_job(files[-1], rows, cut) == 0:
            files.append(folder / f"{len(files)}.csv")
    for path in files:
        assert run_job(path, 0) == 0
    return files


def test_a_sweep_killed_at_20_points_has_every_row_once_with_the_same_numbers(tmp_path):
    clean = tmp_path / "clean.csv"
    assert run_job(clean, 0) == 0
    expected = pd.read_csv(clean)[EXACT].sort_values("identity").reset_index(drop=True)
    points = kill_points()
    folders = [tmp_path / f"chain{i}" for i in range(CHAINS)]
    for folder in folders:
        folder.mkdir()
    with concurrent.futures.ThreadPoolExecutor(CHAINS) as pool:
        chains = pool.map(killed_and_rerun, folders, [points[i::CHAINS] for i in range(CHAINS)])
        files = [path for chain in chains for path in chain]
    assert len(files) >= CHAINS
    for path in files:
        text = path.read_text()
        assert text.endswith("\n")
        table = pd.read_csv(path)
        assert table["identity"].is_unique, f"{path.name}: a row twice"
        got = table[EXACT].sort_values("identity").reset_index(drop=True)
        pd.testing.assert_frame_equal(got, expected, check_exact=True)


def test_a_cluster_sweep_survives_a_killed_worker(tmp_path):
    run_or_fail(
        [sys.executable, str(HERE / "cluster_kill_job.py"), str(tmp_path)], 400, "the kill job"
    )
    killed = json.loads((tmp_path / "killed.json").read_text())
    local = pd.read_csv(tmp_path / "local.csv")
    cluster = pd.read_csv(tmp_path / "killed.csv")
    assert 3 <= killed["rows_before"] < len(local)  # killed mid-sweep
    assert all(a.startswith("tcp://127.0.0.1:") for a in killed["addresses"])  # loopback only
    assert cluster["identity"].is_unique and len(cluster) == len(local)
    columns = EXACT + ["device", "renderer", "shutter", "reference"]
    sort = ["identity"]
    pd.testing.assert_frame_equal(
        cluster[columns].sort_values(sort).reset_index(drop=True),
        local[columns].sort_values(sort).reset_index(drop=True),
        check_exact=True,
    )
