"""Benchmarks of the studies' throughput: sweep evaluations per second, a sweep on 1, 2, ...
Dask workers, and the `blurlab study` command's wall time."""

from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from blurlab import metrics
from blurlab.methods import blur
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies.cluster import forget_scenes
from blurlab.studies.cluster_devices import local_cluster
from blurlab.studies.sweep import default_grids, grid_points, sweep

from .core import Benchmark, register
from .filters import GRID
from .timing import split, tile_filters, wall_ms

SIZES = {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)}


def _sweep_throughput(ctx, size, p, out) -> None:
    scene = scenes.teapot_pass()
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=64, progress=False)
    swept = tile_filters()[0]
    rows = []
    for timed, ssim in ((True, False), (False, False), (False, True)):
        for k, s in GRID[:2]:  # warm up
            blur(ctx, frame, swept, k=k, samples=s, timed=timed)
        start = time.perf_counter()
        for i in range(p["evaluations"]):
            k, s = GRID[i % len(GRID)]
            result = blur(ctx, frame, swept, k=k, samples=s, timed=timed)
            color = result.textures["color"]
            if ssim:  # both from one pass, as sweeps do
                mse, _ = metrics.gpu_mse_ssim(ctx, reference.texture, color)
            else:
                mse = metrics.gpu_mse(ctx, color, reference.texture)
            metrics.psnr_from_mse(mse)  # the scalar read back
        rate = p["evaluations"] / (time.perf_counter() - start)
        mode = ("timer query per pass" if timed else "untimed") + (", PSNR + SSIM" if ssim else "")
        out.figure(f"evaluations, {mode}", rate, "1/s")
        rows.append([mode, rate, 1e3 / rate])
    out.table(
        f"{swept} (k, S cycling) + the error reduced on the GPU, PSNR read back",
        [("mode", ""), ("evaluations", "1/s"), ("per evaluation", "ms")],
        rows,
    )
    color = blur(ctx, frame, swept, timed=False).textures["color"]
    ways = {
        "NumPy metrics.ssim + downloads": lambda: metrics.ssim(
            reference.texture.download(), color.download()
        ),
        "GPU metrics.gpu_ssim": lambda: metrics.gpu_ssim(ctx, reference.texture, color),
    }
    for way, call in ways.items():
        call()  # compile, JIT on llvmpipe
        out.figure(f"SSIM, {way}", statistics.median(wall_ms(call, p["ssim_repeats"])), "ms")


register(
    Benchmark(
        "sweep_throughput",
        "sweep evaluations per second (blur + GPU-reduced error), and SSIM in NumPy against "
        "SSIM on the GPU",
        {
            "evaluations": Param(200, int, "evaluations per mode", 1, 1_000_000),
            "ssim_repeats": Param(10, int, "SSIM calls per way (median)", 1, 10_000),
        },
        _sweep_throughput,
        SIZES,
        {
            "tiny": {"evaluations": 4, "ssim_repeats": 1},
            "software": {"evaluations": 100, "ssim_repeats": 5},
            "gpu": {"evaluations": 2000},
        },
    )
)

COMPARED = ("psnr", "ssim", "flip", "reference_samples")


def _same_rows(a, b) -> bool:
    """Every compared column equal, bit for bit, row by row (scene, method, params)."""
    keys = ["scene", "method", "params"]
    columns = keys + [c for c in COMPARED if c in a.columns]
    a = a[columns].sort_values(keys).reset_index(drop=True)
    b = b[columns].sort_values(keys).reset_index(drop=True)
    return bool(a.equals(b))


def _cluster_sweep(n: int, device: str, arguments: dict, warm: bool):
    """(start-up s, sweep wall s, table) of the sweep on a new cluster of `n` workers."""
    from distributed import Client

    start = time.perf_counter()
    with local_cluster(n, device) as cluster, Client(cluster) as client:
        client.wait_for_workers(n, timeout=300)
        if warm:  # a scene a worker, 16-sample references, then forgotten
            names = [arguments["scenes"][i % len(arguments["scenes"])] for i in range(n)]
            sweep(None, cluster=client, **{**arguments, "scenes": names, "reference_samples": 16})
            client.run(forget_scenes)
        startup = time.perf_counter() - start
        start = time.perf_counter()
        table = sweep(None, cluster=client, **arguments)
        return startup, time.perf_counter() - start, table


def _sweep_scaling(ctx, size, p, out) -> None:
    device = ctx.info()["device"]
    names = split(p["scenes"]) or scenes.names()
    arguments = {
        "scenes": names,
        "methods_and_grids": default_grids(),
        "size": size,
        "reference_samples": p["reference_samples"] or None,
        "metrics": tuple(split(p["metrics"])),
        "repeats": p["repeats"],
        "progress": False,
    }
    evaluations = len(names) * sum(len(grid_points(g)) for g in default_grids().values())
    rows, first, base = [], None, None
    for n in (int(v) for v in split(p["workers"])):
        startup, wall, table = _cluster_sweep(n, device, arguments, p["warm"])
        accounts = table.attrs["workers"].values()
        if sum(a["evaluations"] for a in accounts) != evaluations:
            raise RuntimeError(f"blurlab: sweep_scaling: {n} workers' accounts miss evaluations")
        first = table if first is None else first
        base = base or wall
        same = _same_rows(first, table)
        gpu_s = float((table["total_ms"] * table["repeats"]).sum()) / 1e3
        out.figure(f"{n} worker(s): sweep wall", wall, "s")
        out.figure(f"{n} worker(s): speed-up", base / wall, "x")
        out.figure(f"{n} worker(s): same rows as the first", int(same), "bool")
        rows.append([n, startup, wall, evaluations / wall, gpu_s, base / wall, same])
    out.table(
        f"{len(names)} scenes, {evaluations} evaluations, metrics {p['metrics']}"
        + (", warm clusters" if p["warm"] else ""),
        [
            ("workers", ""),
            ("cluster start", "s"),
            ("sweep wall", "s"),
            ("evaluations", "1/s"),
            ("GPU-timed", "s"),
            ("speed-up", "x"),
            ("same rows", "bool"),
        ],
        rows,
    )


register(
    Benchmark(
        "sweep_scaling",
        "the same sweep on 1, 2, ... Dask workers (bl.local_cluster): wall time, speed-up, "
        "and whether every worker count gave the same rows",
        {
            "workers": Param("1,2", str, "worker counts (comma-separated)"),
            "scenes": Param("", str, "comma-separated scenes (empty: every built-in)"),
            "metrics": Param("psnr,ssim,flip", str, "comma-separated metrics"),
            "reference_samples": Param(0, int, "N of each reference (0: as sweeps choose)", 0),
            "repeats": Param(3, int, "timed runs per evaluation", 1, 100),
            "warm": Param(False, bool, "time clusters that ran a sweep before"),
        },
        _sweep_scaling,
        {"tiny": (48, 27), "software": (160, 90), "gpu": (1920, 1080)},
        {
            "tiny": {
                "workers": "1",
                "scenes": "fan",
                "metrics": "psnr",
                "reference_samples": 8,
                "repeats": 1,
            },
            "software": {"metrics": "psnr,ssim", "repeats": 1, "scenes": "teapot_pass,fan"},
            "gpu": {"metrics": "psnr,ssim", "repeats": 1},
        },
        needs=("distributed",),
    )
)


def _study(ctx, size, p, out) -> None:
    device = ctx.info()["device"]  # the runs open their own contexts on the same kind
    rows = []
    for run in range(p["runs"]):
        with tempfile.TemporaryDirectory() as folder:
            command = [sys.executable, "-m", "blurlab", "--device", device, "study"]
            command += ["--size", f"{size[0]}x{size[1]}", "--out", folder]
            command += ["--scenes", *split(p["scenes"])] if p["scenes"] else []
            command += p["mode"].split()
            start = time.perf_counter()
            done = subprocess.run(command, capture_output=True, text=True)
            if done.returncode != 0:  # say why, not only that it failed
                raise RuntimeError(
                    f"{' '.join(command[2:])} exited with {done.returncode}: "
                    + done.stderr.strip()[-2000:]
                )
            wall = time.perf_counter() - start
            timed = Path(folder) / "phases.json"  # the single-frame study times its phases
            phases = json.loads(timed.read_text()) if timed.exists() else None
        if phases is None:
            rows.append([run, wall, math.nan, "(this mode writes no phases.json)"])
            continue
        shown = ", ".join(f"{k} {v:.1f}" for k, v in phases["phases_s"].items())
        rows.append([run, wall, phases["total_s"], shown])
    out.figure("process wall (median)", statistics.median(r[1] for r in rows), "s")
    clocks = [r[2] for r in rows if math.isfinite(r[2])]
    if clocks:
        out.figure("study clock (median)", statistics.median(clocks), "s")
    out.table(
        "`blurlab study` in a fresh process: interpreter, imports, context and the study",
        [("run", ""), ("process wall", "s"), ("study clock", "s"), ("phases", "s")],
        rows,
    )


register(
    Benchmark(
        "study",
        "the wall time of `blurlab study` as a user runs it, and the phases the study times",
        {
            "runs": Param(1, int, "runs of the command", 1, 100),
            "scenes": Param("", str, "comma-separated scenes (empty: the study's default)"),
            "mode": Param(
                "",
                str,
                "the study's mode flags, e.g. '--sequence' or '--random 100' (each mode keeps a "
                "record of its own, with its scenes)",
            ),
        },
        _study,
        {"tiny": (48, 27), "software": (160, 90), "gpu": (1920, 1080)},
        {"tiny": {"scenes": "fan"}, "software": {"scenes": "teapot_pass,fan"}},
        variants=("mode", "scenes"),
    )
)
