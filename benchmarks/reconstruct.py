"""Time per pass of the reconstruction filter (docs/spec.md §3), compute against fragment backends.

Redoes the Urho3D thesis's Table 5.2 (S sweep at k = 32) and Table 5.3 (k sweep at S = 12) on
this pipeline, and measures the target configuration k = 20, S = 15 with both backends, the
thesis's own pass (reconstruct_urho3d, fragment) and, with --numpy, the NumPy reference.
Input: the G-buffer of teapot_pass at each size, kept on the GPU. Medians over --runs after
two warm-up runs; GL timer queries on a GPU, glFinish + wall clock on llvmpipe.

    python benchmarks/reconstruct.py [--device gpu] [--sizes 1280x720,1920x1080] [--runs 20]
"""

from __future__ import annotations

import argparse
import statistics
import time

import blurlab as bl

from common import describe, open_context, save

PASSES = ("tile_max", "neighbor_max", "reconstruct")


def measure(ctx, frame, method, runs, **params) -> dict:
    for _ in range(2):
        bl.blur(ctx, frame, method, **params)
    per_pass = {name: [] for name in PASSES}
    for _ in range(runs):
        result = bl.blur(ctx, frame, method, **params)
        for name in PASSES:
            per_pass[name].append(result.timings[name].ms)
    medians = {name: statistics.median(v) for name, v in per_pass.items()}
    return {**medians, "total": sum(medians.values()), "clock": result.clock}


def row(label, m) -> str:
    return (
        f"| {label} | {m['tile_max']:.4f} | {m['neighbor_max']:.4f} | "
        f"{m['reconstruct']:.4f} | {m['total']:.4f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--sizes", default="640x360")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--samples", default="5,8,12,15,20,25", help="S sweep at k = 32")
    parser.add_argument("--ks", default="4,8,16,32,64", help="k sweep at S = 12")
    parser.add_argument("--numpy", action="store_true", help="also time the NumPy reference")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    record = {**describe(ctx), "runs": args.runs, "sizes": {}}
    print(f"\n{record['date']}  {record['renderer']}  (medians of {args.runs} runs, ms)")
    header = "| {} | tile_max | neighbor_max | reconstruct | total |\n|---|---|---|---|---|"

    for size in args.sizes.split(","):
        width, height = (int(v) for v in size.split("x"))
        frame = ctx.render(bl.scenes.teapot_pass(), (width, height))
        out = record["sizes"][size] = {}
        print(f"\n### {size}: k = 20, S = 15\n")
        print(header.format("method / backend"))
        for backend in ("compute", "fragment"):
            m = out[f"mcguire2012/{backend}"] = measure(
                ctx, frame, "reconstruct_mcguire2012", args.runs, backend=backend, k=20, samples=15
            )
            print(row(f"reconstruct_mcguire2012 / {backend}", m))
        m = out["urho3d/fragment"] = measure(
            ctx, frame, "reconstruct_urho3d", args.runs, k=20, samples=15
        )
        print(row("reconstruct_urho3d / fragment", m))
        ratio = out["mcguire2012/fragment"]["total"] / out["mcguire2012/compute"]["total"]
        out["fragment_over_compute"] = ratio
        print(f"\nfragment / compute, same algorithm: {ratio:.1f}x")
        if args.numpy:
            twin = bl.method("reconstruct_mcguire2012")
            times = []
            for _ in range(3):
                start = time.perf_counter()
                twin.twin_output(frame)
                times.append((time.perf_counter() - start) * 1e3)
            out["numpy_ms"] = statistics.median(times)
            speedup = out["numpy_ms"] / out["mcguire2012/compute"]["total"]
            print(f"NumPy reference: {out['numpy_ms']:.1f} ms (wall); GPU {speedup:.1f}x faster")

        for title, sweep in (
            ("Table 5.2: S sweep at k = 32", "samples"),
            ("Table 5.3: k sweep at S = 12", "k"),
        ):
            print(f"\n### {size}: {title}\n")
            print("| " + sweep + " | compute total | fragment total | fragment / compute |")
            print("|---|---|---|---|")
            values = args.samples if sweep == "samples" else args.ks
            for value in (int(v) for v in values.split(",")):
                params = (
                    {"k": 32, "samples": int(value)}
                    if sweep == "samples"
                    else {"k": int(value), "samples": 12}
                )
                c = measure(
                    ctx, frame, "reconstruct_mcguire2012", args.runs, backend="compute", **params
                )
                f = measure(
                    ctx, frame, "reconstruct_mcguire2012", args.runs, backend="fragment", **params
                )
                out[f"{sweep}={value}"] = {"compute": c, "fragment": f}
                ratio = f["total"] / c["total"]
                print(f"| {value} | {c['total']:.4f} | {f['total']:.4f} | {ratio:.1f}x |")
    save(args.json, record)


if __name__ == "__main__":
    main()
