"""Issue 19, "fewer, fuller dispatches": the tile filters per pass on one G-buffer of
teapot_pass (McGuire 2012 at k = 20, S = 15; Guertin 2014 at its defaults), compute and
fragment, by speed_floor.filters. Since NeighborMax moved into the reconstruct pass's prologue
on the compute backend (docs/spec.md §3.6) the compute rows list two passes; run the same
script on a tree from before the change (benchmarks/gpu.sh's BASELINE) for the three-pass
figures. Medians over --runs; GL timer queries on a GPU, glFinish + wall clock on llvmpipe.

    python benchmarks/fused_neighbor_max.py [--device software] [--size 640x360] [--runs 10]
"""

from __future__ import annotations

import argparse

from speed_floor import filters

import blurlab as bl

from common import describe, open_context, save


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    frame = ctx.render(bl.scenes.teapot_pass(), size)
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, medians of {args.runs} runs")
    record["filters"] = filters(ctx, frame, args.runs)
    save(args.json, record)


if __name__ == "__main__":
    main()
