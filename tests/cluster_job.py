"""The cluster half of test_sweep_cluster.py, run in a process of its own: Dask's workers are
spawned processes, and a cluster that hangs is then killed with its whole process group.

    python tests/cluster_job.py FOLDER

Writes into FOLDER: local.csv (the sweep in this process), one.csv (one worker), two.csv (two
workers), resumed.csv (a partial sweep through `blurlab sweep --scheduler`, then the whole
sweep on the cluster) and workers.json (the scenes each worker kept).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SCENES = ["fan", "teapot_pass"]
GRID = {"reconstruct_mcguire2012": {"k": [8, 16], "samples": [5, 9]}, "gather_box": {"taps": [4]}}
OPTIONS = {"size": (64, 36), "reference_samples": 16, "progress": False, "repeats": 1}


def main(folder: Path) -> None:
    import blurlab as bl
    from blurlab import cli

    bl.sweep(bl.Context(), SCENES, GRID, out=folder / "local.csv", **OPTIONS)
    with bl.local_cluster(1) as cluster:
        bl.sweep(None, SCENES, GRID, out=folder / "one.csv", cluster=cluster, **OPTIONS)
        cluster.scale(2)
        from distributed import Client

        with Client(cluster) as client:
            client.wait_for_workers(2, timeout=120)
            client.run(_forget)  # the second sweep starts with no frames or references kept
            bl.sweep(None, SCENES, GRID, out=folder / "two.csv", cluster=client, **OPTIONS)
            kept = client.run(_kept_scenes)
            config = folder / "partial.toml"
            config.write_text(
                f"scenes = {json.dumps(SCENES[:1])}\nsize = [64, 36]\nreference_samples = 16\n"
                'metrics = ["psnr", "ssim", "flip", "psnr_aa"]\n'
                f'out = "{(folder / "resumed.csv").as_posix()}"\n'
                "[methods.gather_box]\ntaps = [4]\n"
            )
            assert cli.main(["sweep", str(config), "--scheduler", cluster.scheduler_address]) == 0
            table = bl.sweep(
                None, SCENES, GRID, out=folder / "resumed.csv", cluster=cluster, **OPTIONS
            )
            table.to_csv(folder / "resumed_table.csv", index=False)
    (folder / "workers.json").write_text(json.dumps({str(k): v for k, v in kept.items()}))


def _forget() -> None:
    from blurlab.studies import cluster

    cluster._worker_state.get("scenes", {}).clear()


def _kept_scenes() -> list[int]:
    """Indices of the scenes whose reference this worker rendered in the last sweep."""
    from blurlab.studies import cluster

    return sorted(index for _, index in cluster._worker_state.get("scenes", {}))


if __name__ == "__main__":
    main(Path(sys.argv[1]))
