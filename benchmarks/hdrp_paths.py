"""engine_hdrp's per-tile paths (docs/spec.md §17.4): on every built-in and failure scene, the
share of tiles that take the early-out, fast and slow paths, with the 3 x 3 neighbourhood of
32 px tiles and with the scattered one of 16 px tiles; PSNR against the converged reference and
ms per pass (median of --runs timed runs after one warm-up; glFinish and a wall clock on
llvmpipe, timer queries on a GPU). Also the same at fast_ratio 1 (fast path only for exactly
uniform neighbourhoods), to show what the fast path costs in accuracy.

    python benchmarks/hdrp_paths.py [--device gpu] [--size 640x360] [--runs 5] [--json PATH]
        [--scenes a,b,...]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import pandas as pd

import blurlab as bl

from common import describe, open_context, save

METHOD = "engine_hdrp"
VARIANTS = {
    "gather": {},
    "scatter": {"scatter": True},
    "gather_exact_fast": {"fast_ratio": 1.0},
}


def measure(ctx, scene_name: str, size, runs: int) -> list[dict]:
    scene = bl.scenes.get(scene_name)
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples="auto", progress=False)
    rows = []
    for variant, params in VARIANTS.items():
        out = bl.blur(ctx, frame, METHOD, **params)  # warm-up: shaders compiled
        classes = out.buffers["neighborhood"][..., 3].astype(int).ravel()
        shares = np.bincount(classes, minlength=3) / classes.size
        times, passes = [], {}
        for _ in range(runs):
            timed = bl.blur(ctx, frame, METHOD, **params)
            times.append(timed.total_ms)
            for key, t in timed.timings.items():
                passes.setdefault(key, []).append(t.ms)
            del timed
        rows.append(
            {
                "scene": scene_name,
                "variant": variant,
                "early_out": shares[0],
                "fast": shares[1],
                "slow": shares[2],
                "tiles": int(classes.size),
                "psnr": bl.metrics.psnr(reference.color, out.color),
                "ms": statistics.median(times),
                "passes": {key: statistics.median(v) for key, v in passes.items()},
            }
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--scenes", default=None, help="comma-separated; default: all")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    scenes = (
        args.scenes.split(",") if args.scenes else bl.scenes.names() + bl.scenes.names("failure")
    )
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    start = time.perf_counter()
    rows = []
    for scene_name in scenes:
        rows += measure(ctx, scene_name, size, args.runs)
    record["seconds"] = round(time.perf_counter() - start, 1)
    table = pd.DataFrame(rows)
    print(f"{record['date']}  {record['renderer']}  {args.size}")
    for variant, part in table.groupby("variant", sort=False):
        print(f"\n{variant}")
        print(part.set_index("scene")[["early_out", "fast", "slow", "psnr", "ms"]].round(3))
    medians = table.groupby("variant", sort=False)[["early_out", "fast", "slow", "psnr", "ms"]]
    print("\nmedian over scenes")
    print(medians.median().round(3).to_string())
    record["rows"] = rows
    save(args.json, record)


if __name__ == "__main__":
    main()
