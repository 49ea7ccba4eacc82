"""Time of every registered method on teapot_pass, and of the reference per sub-frame.

Each method runs at its declared defaults on the G-buffer at the instant it declares. Medians
over --runs after one warm-up run; each pass by the context's clock (GL timer queries on a
GPU, glFinish + wall clock on llvmpipe). Methods that render (accumulation, stochastic) include
their renders.

    python benchmarks/methods.py [--device gpu] [--size 1920x1080] [--runs 10]
"""

from __future__ import annotations

import argparse
import statistics

import blurlab as bl

from common import describe, open_context, save


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--reference-samples", type=int, default=64)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    width, height = (int(v) for v in args.size.split("x"))
    scene = bl.scenes.teapot_pass()
    record = {**describe(ctx), "size": args.size, "scene": "teapot_pass", "methods": {}}
    print(
        f"\n{record['date']}  {record['renderer']}  teapot_pass {args.size}, medians of {args.runs}"
    )
    print("\n| method | parameters | instant | total ms | passes (ms) | clock |")
    print("|---|---|---|---|---|---|")
    for name in bl.methods():  # each at its declared defaults
        params = {}
        instant = bl.method_instant(name, params)
        frame = ctx.render(scene, (width, height), instant=instant)
        bl.blur(ctx, frame, name, **params)
        # Keep timings, not results: a live result holds its textures out of the pool, and
        # fresh allocations cost GPU time on first use (docs/benchmarks.md).
        runs = []
        for _ in range(args.runs):
            result = bl.blur(ctx, frame, name, **params)
            runs.append(({p: t.ms for p, t in result.timings.items()}, result.clock))
            del result
        per_pass = {p: statistics.median(r[0][p] for r in runs) for p in runs[0][0]}
        total = statistics.median(sum(r[0].values()) for r in runs)
        clock = runs[0][1]
        record["methods"][name] = {
            "params": params,
            "instant": instant,
            "total_ms": total,
            "passes_ms": per_pass,
            "clock": clock,
        }
        passes = ", ".join(f"{p} {v:.3f}" for p, v in per_pass.items())
        print(f"| {name} | {params} | {instant} | {total:.3f} | {passes} | {clock} |")
    reference = ctx.reference(
        scene, (width, height), samples=args.reference_samples, progress=False
    )
    record["reference_ms_per_subframe"] = reference.ms_per_subframe
    print(
        f"\nreference: {reference.ms_per_subframe:.3f} ms per sub-frame (G-buffer pass + "
        f"accumulation, {reference.clock}), N = {args.reference_samples}"
    )
    save(args.json, record)


if __name__ == "__main__":
    main()
