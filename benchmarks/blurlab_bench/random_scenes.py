"""The random-scene benchmark (docs/spec.md §22): N random scenes, each with its converged
reference, every sweepable method at its default parameters scored by PSNR, SSIM and FLIP, on
one device or spread over Dask workers as sweeps are (several may share a GPU, filling the time
one process leaves it idle while building draws and reading metrics back); and the G-buffer
digests of the first seeds, which tell whether two devices drew the same scenes."""

from __future__ import annotations

import hashlib
import time
from pathlib import Path

import numpy as np
import pandas as pd

from blurlab.core.context import Context
from blurlab.io import images as io
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies.cluster import ACCOUNT, WORKER_COUNTERS
from blurlab.studies.cluster_devices import local_cluster
from blurlab.studies.sweep import sweep, sweep_methods

from .core import Benchmark, register
from .rescore import RESCORED, rescore

METRICS = ("psnr", "ssim", "flip")


def _sweeps(ctx, size, p, names: list[str], workers: int, gpus: int) -> tuple[list, float]:
    """Sweeps `names` in batches of p["batch"] scenes, on `ctx` or on a local cluster of
    `workers` workers (worker i on GPU i modulo `gpus`, 0: all GPUs); starts no batch once
    p["budget_s"] (> 0) has passed since the first. Returns the batches' tables and the seconds
    the cluster took to start, its workers connected (0 without one)."""
    methods = sweep_methods()
    grids = {name: {} for name in methods}  # one point each: the defaults
    arguments = {
        "methods_and_grids": grids,
        "size": size,
        "reference_samples": p["reference_samples"] or None,
        "metrics": METRICS,
        "repeats": 0,  # scored, not timed: no warm-up or timed runs
        "progress": False,
        # a scene's evaluations in one task: its reference is made where it is used, never
        # sent between workers
        "chunk_size": len(methods),
    }
    batches = [names[i : i + p["batch"]] for i in range(0, len(names), p["batch"])]

    def run_batches(device, cluster=None) -> list:
        tables, start = [], time.perf_counter()
        for batch in batches:
            if p["budget_s"] and time.perf_counter() - start > p["budget_s"]:
                break
            tables.append(sweep(device, batch, cluster=cluster, **arguments))
        return tables

    if workers == 1:
        return run_batches(ctx), 0.0
    from distributed import Client

    start = time.perf_counter()
    device = ctx.info()["device"]
    with local_cluster(workers, device, gpus=gpus or None) as cluster, Client(cluster) as client:
        client.wait_for_workers(workers, timeout=300)
        startup = time.perf_counter() - start
        return run_batches(None, client), startup


# The phases of a worker's account (studies.cluster.worker_report): its ACCOUNT and the rest of
# its busy time, evaluations.
ACCOUNT_PHASES = (*ACCOUNT, "evaluations")


def _worker_seconds(tables: list, workers: int, wall: float) -> dict[str, float]:
    """The workers' seconds in each phase of their accounts over every batch's sweep, and the
    rest of workers x wall as idle ({} on one device: no accounts)."""
    accounts = [a for t in tables for a in t.attrs.get("workers", {}).values()]
    if not accounts:
        return {}
    spent = {phase: sum(a[f"{phase}_s"] for a in accounts) for phase in ACCOUNT_PHASES}
    spent["idle (waiting for work, start, transfers)"] = workers * wall - sum(spent.values())
    return spent


def counts_of(text, what: str, lowest: int) -> list[int]:
    """The `workers` or `gpus` parameter: counts in lowest..64 separated by commas."""
    try:
        counts = [int(part) for part in str(text).split(",")]
    except ValueError:
        counts = []
    if not counts or not all(lowest <= c <= 64 for c in counts):
        raise ValueError(
            f"blurlab: random_scenes {what} must be {what.rstrip('s')} counts in "
            f"{lowest}..64 separated by commas (e.g. 1,4), not {text!r}"
        )
    return counts


def worker_counts(text) -> list[int]:
    """The `workers` parameter: worker counts separated by commas, each run in turn."""
    return counts_of(text, "workers", 1)


def scores_digest(rows) -> str:
    """The first 12 hex digits of the SHA-256 of a method's per-scene PSNR, scene by scene in
    name order, each to 0.001 dB: equal in two records where every scene scored the same."""
    ordered = rows.sort_values("scene")
    text = "\n".join(f"{s}:{v:.3f}" for s, v in zip(ordered["scene"], ordered["psnr"], strict=True))
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _random_scenes(ctx, size, p, out) -> None:
    results = Path(str(p["results"])) if p["results"] else None
    if results is not None and not results.parent.is_dir():  # before, not after, the sweep
        raise ValueError(
            f"blurlab: random_scenes results must be a file in an existing folder, not "
            f"{str(results)!r}"
        )
    names = [scenes.random_name(seed) for seed in range(p["seed"], p["seed"] + p["scenes"])]
    listed = (
        sum(d["kind"] == "gpu" for d in Context.devices())
        if ctx.info()["device"] != "software"
        else 0
    )
    runs = [(g, w) for g in counts_of(p["gpus"], "gpus", 0) for w in worker_counts(p["workers"])]
    for gpus, workers in runs:  # the last run's table is reported below
        start = time.perf_counter()
        tables, startup = _sweeps(ctx, size, p, names, workers, gpus)
        wall = time.perf_counter() - start - startup  # the cluster's start is reported apart
        table = pd.concat(tables, ignore_index=True)
        # concat keeps no attrs that differ between the batches' tables
        table.attrs.update({n: sum(t.attrs[n] for t in tables) for n in WORKER_COUNTERS})
        done = table["scene"].nunique()
        each = f"{workers} worker{'s' * (workers > 1)}"
        used = min(gpus or listed, listed)
        if used and workers > 1:
            each += f" on {used} GPU{'s' * (used > 1)}"
        out.figure(f"{each}: scenes", done, "scenes")
        out.figure(f"{each}: evaluations", len(table), "evaluations")
        out.figure(f"{each}: cluster start (not in the wall)", startup, "s")
        out.figure(f"{each}: wall (references, G-buffers, methods, metrics)", wall, "s")
        out.figure(f"{each}: scenes per second", done / wall, "1/s")
        projected = wall * p["scenes"] / done
        out.figure(f"{each}: projected wall for {p['scenes']} scenes", projected, "s")
        waits = table.attrs["fence_timeouts"]
        out.figure(f"{each}: waits for the GPU that the driver cut short", waits, "waits")
        paced = table.attrs["pacing_waits"]
        out.figure(f"{each}: waits at the bound on unfinished passes", paced, "waits")
        out.figure(
            f"{each}: chunks evaluated again on a new context after a GPU reset",
            table.attrs["context_resets"],
            "chunks",
        )
        spent = _worker_seconds(tables, workers, wall)
        if spent:
            out.table(
                f"{each}: where the workers' seconds went, summed over the workers",
                [("phase", ""), ("worker seconds", "s"), ("share", "%")],
                [[phase, s, 100 * s / (workers * wall)] for phase, s in spent.items()],
            )
    if results is not None:
        io.write_text(results, table.to_csv(index=False))
    rows = []
    for method, rows_of in table.groupby("method", sort=True):
        psnr = rows_of["psnr"].to_numpy(float)
        rows.append(
            [
                method,
                float(np.nanmedian(psnr)),
                float(np.nanmean(psnr)),
                float(np.nanpercentile(psnr, 10)),
                float(np.nanmedian(rows_of["ssim"])),
                float(np.nanmedian(rows_of["flip"])),
                scores_digest(rows_of),
            ]
        )
    out.table(
        f"each method at its defaults over {done} random scenes (seeds from {p['seed']}); the "
        "digest of its per-scene PSNR tells two records' scenes apart where a median hides it",
        [
            ("method", ""),
            ("median PSNR", "dB"),
            ("mean PSNR", "dB"),
            ("10th percentile PSNR", "dB"),
            ("median SSIM", ""),
            ("median FLIP", ""),
            ("PSNR digest", ""),
        ],
        rows,
    )
    rescore(ctx, table, size, p, METRICS, out)
    digests = []
    for seed in range(p["seed"], p["seed"] + min(p["hashed"], p["scenes"])):
        frame = ctx.render(scenes.random(seed), size)
        speed = np.linalg.norm(frame.motion, axis=-1)
        mean = frame.color[..., :3].mean(axis=(0, 1))
        digests.append(
            [seed, scenes.gbuffer_digest(frame)[:16], *(float(c) for c in mean), speed.mean()]
        )
        del frame
    out.table(
        "G-buffer digests (SHA-256 of colour, depth, motion and ids; first 16 hex digits) and "
        "means, to compare devices",
        [
            ("seed", ""),
            ("digest", ""),
            ("mean R", ""),
            ("mean G", ""),
            ("mean B", ""),
            ("mean motion length", "px"),
        ],
        digests,
    )


register(
    Benchmark(
        "random_scenes",
        "N random scenes (bl.scenes.random) with references, every sweepable method at its "
        "defaults scored by PSNR, SSIM and FLIP: wall time and scenes per second, on one "
        "device or on `workers` Dask workers",
        {
            "scenes": Param(20, int, "random scenes, seeds seed..seed+scenes-1", 1, 100_000),
            "seed": Param(0, int, "the first seed", 0),
            "workers": Param(
                "1",
                str,
                "Dask workers, worker i on GPU i modulo the GPUs, so several may share one "
                "(1: this process's context); several counts separated by commas run in turn",
            ),
            "gpus": Param(
                "0",
                str,
                "GPUs the workers spread over, the first that many (0: all); several counts "
                "separated by commas run in turn, each with every worker count",
            ),
            "batch": Param(50, int, "scenes a sweep call", 1, 100_000),
            "budget_s": Param(
                0.0, float, "start no batch after this many seconds (0: no limit)", 0.0
            ),
            "reference_samples": Param(0, int, "N of each reference (0: as sweeps choose)", 0),
            "hashed": Param(4, int, "first seeds whose G-buffer digest is recorded", 0, 1000),
            "results": Param("", str, "a .csv every scene's scores go to (empty: none)"),
            "rescored": RESCORED,
        },
        _random_scenes,
        {"tiny": (48, 27), "software": (320, 180), "gpu": (1920, 1080)},
        {
            "tiny": {"scenes": 2, "reference_samples": 8, "hashed": 2, "rescored": 3},
            "software": {"scenes": 24, "batch": 24},
            # eight processes share one GPU, as the H100 record ran (one process leaves the GPU
            # idle while it builds draws and reads metrics back); the budget, with the last
            # batch started before it, keeps a slower GPU's run inside a 10-minute call (the
            # H100 ran all 1000 scenes in 489 s)
            "gpu": {"scenes": 1000, "workers": "8", "budget_s": 530.0},
        },
    )
)
