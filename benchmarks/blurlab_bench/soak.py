"""Soak: many sweep evaluations in one process, watching what it holds (docs/reliability.md,
"Soak").

N evaluations, each what a sweep does for a row (blurlab.studies.evaluation: a timed run, an
untimed run and its metrics against the scene's reference), cycling through every sweepable
method at the middle of its default grid on one scene. Along the way it samples the process's
resident memory (RSS), the live GL objects blurlab made (`ctx.live_objects()`: textures,
buffers, programs, queries, meshes) and, where the driver reports it, free video memory
(`ctx.memory()`: NVIDIA's GL_NVX_gpu_memory_info; llvmpipe reports none, its memory is the
process's). The rows of the last cycle must equal the first cycle's, bit for bit but for the
pass times: a long run gives the numbers a short one does.

    blurlab bench soak [--device software] [--param evaluations=20000] [--size 64x36]

With `--param devices=1,2,3` the evaluations are shared out between one process per listed EGL
device (`blurlab.Context.devices()`; an index listed twice gets two), each its own soak, run
side by side: how a machine of several GPUs soaks more evaluations in the same hour. Each
process is reported apart.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor

from blurlab.core.context import Context
from blurlab.methods import method
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies import evaluation
from blurlab.studies.sweep import middle_point, sweep_methods

from .core import Benchmark, register

SAMPLES = 20  # samples of memory and objects along a run, besides its start and end
COMPARED = ("psnr", "ssim")  # the metrics each evaluation computes and the rows compare
READBACK_BATCH = 16  # evaluations whose metrics are read back together, as bl.sweep's default


def configurations() -> list[tuple[str, dict]]:
    """(method, parameters) of every sweepable method at the middle of its default grid, one
    sub-interval of the shutter."""
    configs = []
    for name in sweep_methods():
        point = {k: v for k, v in middle_point(method(name).default_grid).items() if k != "steps"}
        configs.append((name, point))
    return configs


def rss_mib() -> float | None:
    """This process's resident memory in MiB (Linux /proc), or None elsewhere."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except OSError:
        return None


def sample(ctx: Context, done: int, start: float) -> dict:
    """The process's state after `done` evaluations: RSS, live GL objects, free video memory."""
    gc.collect()  # textures dropped in Python go back to the pool first
    ctx.finish()
    objects = ctx.live_objects()
    vram = ctx.memory()
    return {
        "evaluations": done,
        "seconds": time.perf_counter() - start,
        "rss_mib": rss_mib(),
        "gl_objects": sum(objects.values()),
        "gl_objects_by_kind": objects,
        "vram_available_mib": vram["available"] / 1024 if vram else None,
    }


def soak(ctx: Context, evaluations: int, size, scene: str = "fan", reference_samples: int = 8):
    """Runs `evaluations` sweep evaluations of `scene` at `size` on `ctx`; returns a dict: the
    samples (sample()), at the start (after one warm-up cycle, which compiles every program and
    fills the texture pool), along the run and at its end, the seconds of the run, and whether
    the last cycle's rows equal the first's (`same_rows`), with both cycles' rows."""
    if isinstance(evaluations, bool) or not isinstance(evaluations, int) or evaluations < 1:
        raise ValueError(f"blurlab soak: evaluations must be an integer >= 1, not {evaluations!r}")
    configs = configurations()
    jobs = [(name, point, None, i) for i, (name, point) in enumerate(configs)]
    settings = evaluation.Settings(
        (int(size[0]), int(size[1])),
        None,
        reference_samples,
        COMPARED,
        repeats=1,
        readback_batch=READBACK_BATCH,
    )
    the_scene = scenes.get(scene)
    cache: dict = {}

    def cycle(count: int) -> list[dict]:
        rows = evaluation.evaluate_scene(ctx, the_scene, jobs[:count], settings, cache)
        return [{k: row[k] for k in ("method", "params", *COMPARED)} for _, row in rows]

    first = cycle(len(jobs))  # the warm-up cycle: its rows are the short run's
    start = time.perf_counter()
    samples = [sample(ctx, 0, start)]
    every = max(1, evaluations // SAMPLES)
    done, last = 0, []
    while done < evaluations:
        count = min(len(jobs), evaluations - done)
        last = cycle(count)
        done += count
        if done // every != (done - count) // every or done == evaluations:
            samples.append(sample(ctx, done, start))
    seconds = time.perf_counter() - start
    compared = first[: len(last)]
    return {
        "evaluations": evaluations,
        "seconds": seconds,
        "configurations": len(configs),
        "samples": samples,
        "same_rows": last == compared,
        "first_rows": compared,
        "last_rows": last,
    }


def figures(result: dict) -> dict:
    """The run's figures: evaluations, seconds, RSS, GL objects and free video memory at its
    start and end and their growth (None where not reported), and whether the rows held."""
    start, end = result["samples"][0], result["samples"][-1]

    def growth(key):
        return None if start[key] is None else end[key] - start[key]

    return {
        "evaluations": result["evaluations"],
        "seconds": result["seconds"],
        "evaluations_per_s": result["evaluations"] / result["seconds"],
        "rss_start_mib": start["rss_mib"],
        "rss_end_mib": end["rss_mib"],
        "rss_growth_mib": growth("rss_mib"),
        "rss_max_mib": max(s["rss_mib"] or 0 for s in result["samples"]),
        "gl_objects_start": start["gl_objects"],
        "gl_objects_end": end["gl_objects"],
        "gl_objects_growth": end["gl_objects"] - start["gl_objects"],
        "vram_available_start_mib": start["vram_available_mib"],
        "vram_available_end_mib": end["vram_available_mib"],
        "same_rows_as_a_short_run": result["same_rows"],
    }


def device_indices(text) -> list[int]:
    """The EGL device indices of the `devices` parameter ("" for none, else "1,2,3")."""
    text = str(text)
    try:
        indices = [int(part) for part in text.split(",") if part.strip()]
    except ValueError:
        indices = []
    if text.strip() and (not indices or min(indices) < 0):
        raise ValueError(
            "blurlab soak: devices must be EGL device indices separated by commas, an index "
            f"given twice for two processes on it (see blurlab.Context.devices()), not {text!r}"
        )
    return indices


def soak_on_device(index: int, evaluations: int, size, scene: str) -> dict:
    """soak() in a context of its own on EGL device `index` (a worker process's job)."""
    ctx = Context(index)
    result = soak(ctx, evaluations, size, scene)
    result["device"] = f"{index}: {ctx.info()['renderer']}"
    return result


def soak_side_by_side(indices: list[int], evaluations: int, size, scene: str) -> list[dict]:
    """soak() in one process per device of `indices`, `evaluations` shared out between them,
    all at once; the results in the order of `indices`."""
    count = len(indices)
    shares = [evaluations // count + (i < evaluations % count) for i in range(count)]
    spawn = multiprocessing.get_context("spawn")  # a fresh GL stack per process, never a fork
    with ProcessPoolExecutor(count, mp_context=spawn) as pool:
        jobs = [
            pool.submit(soak_on_device, index, share, size, scene)
            for index, share in zip(indices, shares, strict=True)
        ]
        return [job.result() for job in jobs]


def _soak(ctx, size, p, out) -> None:
    indices = device_indices(p["devices"])
    if indices:
        results = soak_side_by_side(indices, p["evaluations"], size, p["scene"])
    else:
        results = [soak(ctx, p["evaluations"], size, p["scene"])]
        results[0]["device"] = ctx.info()["renderer"]
    for result in results:
        if not result["same_rows"]:
            raise RuntimeError(
                f"blurlab: soak on {result['device']}: the last cycle's rows differ from the "
                f"first's: {result['first_rows']} then {result['last_rows']}"
            )
    if indices:
        report_side_by_side(results, out)
    else:
        report_one(results[0], out)


def report_side_by_side(results: list[dict], out) -> None:
    """Figures over every process of a side-by-side soak, and a row per process."""
    each = [figures(result) for result in results]
    total = sum(f["evaluations"] for f in each)
    seconds = max(f["seconds"] for f in each)
    out.figure("evaluations", total, "")
    out.figure("processes (one per device)", len(each), "")
    out.figure("seconds", seconds, "s")
    out.figure("evaluations per second", total / seconds, "1/s")
    out.figure("largest RSS growth of a process", max(f["rss_growth_mib"] for f in each), "MiB")
    out.figure("largest live GL objects growth", max(f["gl_objects_growth"] for f in each), "")
    out.figure("rows of the last cycle equal to the first's", 1, "yes")
    out.table(
        "each process (free video memory: NVIDIA's GL_NVX_gpu_memory_info)",
        [("device", ""), ("evaluations", ""), ("seconds", "s"), ("RSS at the start", "MiB")]
        + [("RSS at the end", "MiB"), ("live GL objects at the start", "")]
        + [("live GL objects at the end", ""), ("free video memory at the start", "MiB")]
        + [("free video memory at the end", "MiB")],
        [
            [result["device"], f["evaluations"], f["seconds"], f["rss_start_mib"]]
            + [f["rss_end_mib"], f["gl_objects_start"], f["gl_objects_end"]]
            + [f["vram_available_start_mib"], f["vram_available_end_mib"]]
            for result, f in zip(results, each, strict=True)
        ],
    )


def report_one(result: dict, out) -> None:
    """Figures of a soak in this process, and its samples."""
    f = figures(result)
    out.figure("evaluations", f["evaluations"], "")
    out.figure("seconds", f["seconds"], "s")
    out.figure("evaluations per second", f["evaluations_per_s"], "1/s")
    out.figure("RSS at the start", f["rss_start_mib"], "MiB")
    out.figure("RSS at the end", f["rss_end_mib"], "MiB")
    out.figure("RSS growth", f["rss_growth_mib"], "MiB")
    out.figure("live GL objects at the start", f["gl_objects_start"], "")
    out.figure("live GL objects at the end", f["gl_objects_end"], "")
    out.figure("live GL objects growth", f["gl_objects_growth"], "")
    if f["vram_available_start_mib"] is not None:
        out.figure("free video memory at the start", f["vram_available_start_mib"], "MiB")
        out.figure("free video memory at the end", f["vram_available_end_mib"], "MiB")
    out.figure("rows of the last cycle equal to the first's", 1, "yes")
    unreported = "not reported by the driver"
    out.table(
        "samples along the run (free video memory: NVIDIA's GL_NVX_gpu_memory_info)",
        [("evaluations", ""), ("seconds", "s"), ("RSS", "MiB"), ("live GL objects", "")]
        + [("free video memory", "MiB")],
        [
            [s["evaluations"], s["seconds"], s["rss_mib"], s["gl_objects"]]
            + [unreported if s["vram_available_mib"] is None else s["vram_available_mib"]]
            for s in result["samples"]
        ],
    )


register(
    Benchmark(
        "soak",
        "N sweep evaluations in one process: RSS, live GL objects and free video memory along "
        "the way, and the last cycle's rows against the first's",
        {
            "evaluations": Param(
                20_000, int, "sweep evaluations after the warm-up cycle", 1, 10_000_000
            ),  # fmt: skip
            "scene": Param("fan", str, "the built-in scene evaluated"),
            "devices": Param(
                "",
                str,
                "EGL device indices to soak on side by side, one process each "
                "(e.g. 1,2,3 or 1,1,2,2); empty: this context's device",
            ),
        },
        _soak,
        {"tiny": (32, 18), "software": (64, 36), "gpu": (1920, 1080)},
        {"tiny": {"evaluations": 40}, "gpu": {"evaluations": 200_000}},
    )
)
