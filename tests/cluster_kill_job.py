"""A sweep on a local cluster of two workers, one of which is killed (SIGKILL) mid-sweep, for
tests/test_sweep_faults.py; run in a process group of its own (tests/process_group.py).

    python tests/cluster_kill_job.py FOLDER

Writes FOLDER/local.csv (the sweep in this process), FOLDER/killed.csv (the sweep on the
cluster) and FOLDER/killed.json ({"pid": the worker killed, "rows_before": rows in the file
when it was killed, "addresses": the scheduler's and the workers' addresses}).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import threading
import time
from pathlib import Path

SCENES = ["fan", "crossing", "teapot_pass"]
OPTIONS = {"size": (32, 18), "reference_samples": 8, "metrics": ["psnr", "ssim"]}
OPTIONS.update({"progress": False, "repeats": 1, "chunk_size": 1})


def rows_in(path: Path) -> int:
    return max(0, len(path.read_text().splitlines()) - 1) if path.exists() else 0


def main(folder: Path) -> None:
    from distributed import Client
    from method_picks import EXAMPLE, pick

    import blurlab as bl

    # A gather with taps and a tile filter with k (tests/method_picks.py, beside this script).
    grid = {pick(kind="gather", params=("taps",)): {"taps": [2, 4, 6, 8]}, EXAMPLE: {"k": [8, 16]}}
    bl.sweep(bl.Context(), SCENES, grid, out=folder / "local.csv", **OPTIONS)
    out = folder / "killed.csv"
    with bl.local_cluster(2) as cluster, Client(cluster) as client:
        client.wait_for_workers(2, timeout=120)
        pids = client.run(os.getpid)
        victim = pids[sorted(pids)[-1]]
        addresses = [cluster.scheduler_address, *pids]  # every one listens on loopback
        outcome = {}

        def run():
            try:
                bl.sweep(None, SCENES, grid, out=out, cluster=client, **OPTIONS)
            except BaseException as error:  # reported below, with the test's failure
                outcome["error"] = repr(error)

        thread = threading.Thread(target=run)
        thread.start()
        while rows_in(out) < 3 and thread.is_alive():  # mid-sweep: some rows, most to come
            time.sleep(0.01)
        before = rows_in(out)
        os.kill(victim, signal.SIGKILL)
        thread.join(timeout=240)
        if "error" in outcome or thread.is_alive():
            raise SystemExit(f"the sweep did not complete: {outcome or 'still running'}")
    (folder / "killed.json").write_text(
        json.dumps({"pid": victim, "rows_before": before, "addresses": addresses})
    )


if __name__ == "__main__":
    main(Path(sys.argv[1]))
