"""How often engine_unreal (docs/spec.md §17.5) takes each per-tile path: for every built-in
and failure scene, the number of 16 x 16 tiles classified skip, fast and slow, and the median
ms of each pass over --runs runs (on llvmpipe glFinish and a wall clock, on a GPU timer
queries). Prints a table; --json writes the rows.

    python benchmarks/unreal_paths.py [--device gpu] [--size 640x360] [--runs 5] [--json PATH]
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np
import pandas as pd

import blurlab as bl
from blurlab.twins.unreal import CLASS_NAMES

from common import describe, open_context, save

METHOD = "engine_unreal"


def measure(ctx, scene_name: str, size, runs: int) -> dict:
    frame = ctx.render(bl.scenes.get(scene_name), size)
    result = bl.blur(ctx, frame, METHOD)  # warm-up: shaders compiled, textures pooled
    classes = result.buffers["neighbors"][..., 3].astype(int)
    counts = np.bincount(classes.ravel(), minlength=len(CLASS_NAMES))
    passes: dict[str, list[float]] = {}
    for _ in range(runs):
        for key, timing in bl.blur(ctx, frame, METHOD).timings.items():
            passes.setdefault(key, []).append(timing.ms)
    row = {"scene": scene_name, **dict(zip(CLASS_NAMES, counts.tolist(), strict=True))}
    return row | {f"{key} ms": statistics.median(ms) for key, ms in passes.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    scenes = bl.scenes.names() + bl.scenes.names("failure")
    rows = [measure(ctx, name, size, args.runs) for name in scenes]
    table = pd.DataFrame(rows).set_index("scene")
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    print(f"{record['date']}  {record['renderer']}  {args.size}  {METHOD}")
    print(table.round(3).to_string())
    print("total tiles:", table[list(CLASS_NAMES)].sum().to_dict())
    save(args.json, record | {"rows": rows})


if __name__ == "__main__":
    main()
