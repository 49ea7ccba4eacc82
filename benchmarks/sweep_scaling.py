"""Sweep scaling: the same sweep on 1, 2, ... Dask workers (bl.local_cluster), wall time and
speed-up, and whether every worker count gave the same rows.

Each worker is a process with one thread and one device: GPU i for worker i on a multi-GPU
machine (wrapping around when there are more workers than GPUs), llvmpipe otherwise (each
worker then gets an equal share of the cores). The wall time of a sweep runs from bl.sweep's
call to its table, so it includes each worker's context, shader compiles and references;
starting the cluster (with --warm, and its untimed warm-up sweep) is timed apart. "GPU-timed"
adds up every timed pass of every run (warm-up and error runs untimed, so the GPU's real share
is somewhat higher); the rest of the wall time is the CPU's: G-buffer and reference
submission, readback, SSIM and FLIP. After each cluster run, a table says where each worker's
time went (blurlab.studies.cluster's worker_report): context, references, G-buffers, warm-up
runs, references imported from and exported to other workers, evaluations and idle.

    python benchmarks/sweep_scaling.py [--device gpu] [--size 1920x1080] [--workers 1 2]
        [--scenes teapot_pass fan] [--metrics psnr,ssim] [--reference-samples N] [--local]
        [--warm]
"""

from __future__ import annotations

import argparse
import time

import pandas as pd

import blurlab as bl
from blurlab.studies.cluster import account_table, forget_scenes
from blurlab.studies.sweep import default_grids, grid_points

from common import describe, save

COMPARED = ("psnr", "ssim", "flip", "reference_samples")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto", choices=("auto", "gpu", "software"))
    parser.add_argument("--size", default="320x180")
    parser.add_argument("--scenes", nargs="+", default=bl.scenes.names())
    parser.add_argument("--metrics", default="psnr,ssim,flip")
    parser.add_argument("--reference-samples", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument(
        "--local", action="store_true", help="last, time the sweep in this process, no Dask"
    )
    parser.add_argument(
        "--warm",
        action="store_true",
        help="time each cluster as one that has run a sweep before: each worker first runs one "
        "scene's grids at this size, untimed, then forgets its scenes (compiled programs and "
        "texture pools stay)",
    )
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    metrics = tuple(args.metrics.split(","))
    ctx = bl.Context(args.device)
    gpus = [d for d in bl.Context.devices() if d["kind"] == "gpu"]
    sweep_args = {
        "scenes": args.scenes,
        "methods_and_grids": default_grids(),
        "size": (width, height),
        "reference_samples": args.reference_samples,
        "metrics": metrics,
        "repeats": args.repeats,
        "progress": False,
    }
    evaluations = len(args.scenes) * sum(len(grid_points(g)) for g in default_grids().values())
    record = {
        **describe(ctx),
        "size": args.size,
        "scenes": args.scenes,
        "metrics": list(metrics),
        "evaluations": evaluations,
        "egl_gpus": len(gpus),
        "runs": [],
    }
    print(
        f"\n{record['date']}  {record['renderer']}  {args.size}, {len(args.scenes)} scenes, "
        f"{evaluations} evaluations, metrics {','.join(metrics)}; EGL GPUs: {len(gpus)}\n"
    )
    print(
        "| run | cluster start s | sweep wall s | evaluations / s | GPU-timed s | speed-up "
        "| same rows |\n|---|---|---|---|---|---|---|",
        flush=True,
    )
    # Each run's line is printed and saved as soon as it is measured, so a run cut short by a
    # time limit still leaves the ones before it.
    first_table = None
    base = None  # the first cluster run: speed-ups are relative to it
    runs = [(f"{n} worker(s)", n) for n in args.workers] + ([("local", 0)] if args.local else [])
    for name, n in runs:
        if n and gpus and args.device != "software" and n > len(gpus):
            print(f"note: {n} workers share {len(gpus)} GPU(s)", flush=True)
        if n == 0:
            start = time.perf_counter()
            table = bl.sweep(ctx, **sweep_args)
            run = _run(name, 0.0, time.perf_counter() - start, table)
        else:
            run, table = _cluster_run(name, n, args.device, sweep_args, args.warm)
            base = base or run
        first_table = table if first_table is None else first_table
        run["speedup"] = base["wall_s"] / run["wall_s"] if base else float("nan")
        run["same_rows_as_first"] = _same(first_table, table)
        record["runs"].append(run)
        print(
            f"| {name} | {run['startup_s']:.1f} | {run['wall_s']:.1f} "
            f"| {evaluations / run['wall_s']:.2f} | {run['gpu_timed_s']:.1f} "
            f"| {run['speedup']:.2f}x | {run['same_rows_as_first']} |",
            flush=True,
        )
        save(args.json, record)
    for run in record["runs"]:
        if "workers_report" in run:
            _print_workers(run)


def _print_workers(run: dict) -> None:
    """Where each worker's share of the sweep's wall time went (cluster.account_table)."""
    print(f"\n{run['name']}, sweep wall {run['wall_s']:.1f} s:\n")
    print(account_table(run["workers_report"], run["wall_s"]))


def _cluster_run(name: str, n: int, device: str, sweep_args: dict, warm: bool):
    from distributed import Client

    start = time.perf_counter()
    with bl.local_cluster(n, device) as cluster, Client(cluster) as client:
        client.wait_for_workers(n, timeout=300)
        if warm:  # a scene a worker (from the sweep's own, cycled), 16-sample references
            scenes = [sweep_args["scenes"][i % len(sweep_args["scenes"])] for i in range(n)]
            warm_args = {**sweep_args, "scenes": scenes, "reference_samples": 16}
            bl.sweep(None, cluster=client, **warm_args)
            client.run(forget_scenes)
        startup = time.perf_counter() - start
        start = time.perf_counter()
        table = bl.sweep(None, cluster=client, **sweep_args)
        wall = time.perf_counter() - start
    accounts = table.attrs["workers"]
    run = _run(name, startup, wall, table)
    run["workers"] = n
    run["worker_devices"] = sorted(str(r["device"]) for r in accounts.values())
    run["workers_report"] = accounts
    return run, table


def _run(name: str, startup: float, wall: float, table: pd.DataFrame) -> dict:
    timed = table["total_ms"] * table["repeats"]
    return {"name": name, "startup_s": startup, "wall_s": wall, "gpu_timed_s": timed.sum() / 1e3}


def _same(a: pd.DataFrame, b: pd.DataFrame) -> bool:
    """Every compared column equal, bit for bit, row by row (scene, method, params)."""
    keys = ["scene", "method", "params"]
    columns = keys + [c for c in COMPARED if c in a.columns]
    a = a[columns].sort_values(keys).reset_index(drop=True)
    b = b[columns].sort_values(keys).reset_index(drop=True)
    return bool(a.equals(b))


if __name__ == "__main__":
    main()
