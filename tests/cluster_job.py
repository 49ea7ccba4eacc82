"""The cluster half of test_sweep_cluster.py, run in a process of its own: Dask's workers are
spawned processes, and a cluster that hangs is then killed with its whole process group.

    python tests/cluster_job.py FOLDER

Writes into FOLDER: local.csv (the sweep in this process), one.csv (one worker), two.csv (two
workers), resumed.csv (a partial sweep through `blurlab sweep --scheduler`, then the whole
sweep on the cluster), workers.json (each worker's report after the two-worker sweep),
two_accounts.json (the same sweep's table.attrs["workers"]), and
helped.csv with helped_workers.json (one scene on two workers, one configuration a chunk),
and reset.csv with reset.json (the sweep again, each worker's context lost once).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SCENES = ["fan", "teapot_pass"]
OPTIONS = {"size": (64, 36), "reference_samples": 16, "progress": False, "repeats": 1}


def main(folder: Path) -> None:
    from method_picks import EXAMPLE, pick

    import blurlab as bl
    from blurlab import cli
    from blurlab.studies import cluster as cluster_module

    # A tile filter with k and samples and a gather with taps (tests/method_picks.py, beside
    # this script); test_sweep_cluster.py reads the rows, whichever methods they are.
    gather = pick(kind="gather", params=("taps",))
    grid = {EXAMPLE: {"k": [8, 16], "samples": [5, 9]}, gather: {"taps": [4]}}
    bl.sweep(bl.Context(), SCENES, grid, out=folder / "local.csv", **OPTIONS)
    with bl.local_cluster(1) as cluster:
        bl.sweep(None, SCENES, grid, out=folder / "one.csv", cluster=cluster, **OPTIONS)
        cluster.scale(2)
        from distributed import Client

        with Client(cluster) as client:
            client.wait_for_workers(2, timeout=120)
            # The second sweep starts with no frames or references kept.
            client.run(cluster_module.forget_scenes)
            two = bl.sweep(None, SCENES, grid, out=folder / "two.csv", cluster=client, **OPTIONS)
            (folder / "two_accounts.json").write_text(json.dumps(two.attrs["workers"]))
            reports = client.run(cluster_module.worker_report)
            config = folder / "partial.toml"
            config.write_text(
                f"scenes = {json.dumps(SCENES[:1])}\nsize = [64, 36]\nreference_samples = 16\n"
                'metrics = ["psnr", "ssim", "flip", "psnr_aa"]\n'
                f'out = "{(folder / "resumed.csv").as_posix()}"\n'
                f"[methods.{gather}]\ntaps = [4]\n"
            )
            assert cli.main(["sweep", str(config), "--scheduler", cluster.scheduler_address]) == 0
            table = bl.sweep(
                None, SCENES, grid, out=folder / "resumed.csv", cluster=cluster, **OPTIONS
            )
            table.to_csv(folder / "resumed_table.csv", index=False)
            # One scene, a configuration a chunk: the second worker can only help on it.
            client.run(cluster_module.forget_scenes)
            bl.sweep(
                None,
                SCENES[:1],
                grid,
                out=folder / "helped.csv",
                cluster=client,
                chunk_size=1,
                **OPTIONS,
            )
            helped = client.run(cluster_module.worker_report)
            # The GPU resets each worker's context in its next chunk once: the chunk is
            # evaluated again on a new context, and the rows are those of an untroubled sweep.
            client.run(cluster_module.forget_scenes)
            client.run(_lose_the_context_once)
            reset = bl.sweep(
                None, SCENES, grid, out=folder / "reset.csv", cluster=client, **OPTIONS
            )
            resets = client.run(cluster_module.worker_report)
            (folder / "reset.json").write_text(
                json.dumps(
                    {
                        "table": reset.attrs["context_resets"],
                        "workers": {str(k): v["context_resets"] for k, v in resets.items()},
                    }
                )
            )
    (folder / "helped_workers.json").write_text(json.dumps(helped))
    (folder / "workers.json").write_text(json.dumps({str(k): v for k, v in reports.items()}))


def _lose_the_context_once() -> None:
    """On a worker: its next evaluation raises blurlab.ContextLost, as a GPU reset does."""
    import blurlab as bl
    from blurlab.studies import cluster as cluster_module

    evaluate = cluster_module.evaluate_scene

    def lost_once(*args, **kwargs):
        cluster_module.evaluate_scene = evaluate
        raise bl.ContextLost("a GPU reset, as the test has it")

    cluster_module.evaluate_scene = lost_once


if __name__ == "__main__":
    main(Path(sys.argv[1]))
