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

    python -m blurlab.studies.soak --evaluations 20000 --size 64x36 [--device software]
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import sys
import time

from ..context import Context
from ..methods import method
from . import evaluation
from .sweep import middle_point, sweep_methods

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
    from .. import scenes

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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m blurlab.studies.soak", description=__doc__)
    parser.add_argument("--evaluations", type=int, default=20000)
    parser.add_argument("--size", default="64x36", help="WIDTHxHEIGHT")
    parser.add_argument("--device", default="auto")
    parser.add_argument("--scene", default="fan")
    parser.add_argument("--json", help="write the record (figures, samples, device) here")
    args = parser.parse_args(argv)
    size = tuple(int(v) for v in args.size.lower().split("x"))
    device = int(args.device) if args.device.isdigit() else args.device
    ctx = Context(device)
    info = ctx.info()
    result = soak(ctx, args.evaluations, size, args.scene)
    record = {
        "device": info["device"],
        "renderer": info["renderer"],
        "size": list(size),
        "scene": args.scene,
        "figures": figures(result),
        "video_memory": "reported" if ctx.memory() else "not reported by the driver",
        "samples": result["samples"],
    }
    print(json.dumps(record["figures"], indent=1))
    print(f"device: {info['renderer']}; video memory {record['video_memory']}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(record, f, indent=1)
    return 0 if result["same_rows"] else 1


if __name__ == "__main__":
    sys.exit(main())
