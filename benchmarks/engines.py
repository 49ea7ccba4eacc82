"""The engines' motion blur side by side (issue 17): every engine method (engine_*),
gather_coverage, reconstruct_guertin2014 and reconstruct_mcguire2012 at their defaults, on
every built-in and failure scene. PSNR, SSIM and FLIP against the converged reference, and ms
per pass (median of --runs timed runs after one warm-up; on llvmpipe glFinish and a wall clock,
on a GPU timer queries). Prints the table, writes it as JSON (--json), as Markdown (--markdown)
and as a Pareto chart of median ms against median PSNR (--chart); the last two by default
beside the JSON.

    python benchmarks/engines.py [--device gpu] [--size 640x360] [--runs 5] [--json PATH]
        [--markdown PATH] [--chart PATH] [--scenes a,b,...] [--methods a,b,...]
"""

from __future__ import annotations

import argparse
import statistics
import time

import pandas as pd

import blurlab as bl

from common import describe, open_context, save

BASELINES = ("reconstruct_guertin2014", "reconstruct_mcguire2012")
COMBINED = ("gather_coverage",)  # the filter built from the engines' best parts (spec §17.6)


def engine_methods() -> list[str]:
    """The engines' methods from the registry, the filter that combines them, then the filters
    they are measured against."""
    engines = [name for name in bl.methods() if name.startswith("engine_")]
    return engines + list(COMBINED) + list(BASELINES)


def measure(ctx, scene_name: str, size, runs: int, methods) -> list[dict]:
    scene = bl.scenes.get(scene_name)
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples="auto", progress=False)
    rows = []
    for name in methods:
        out = bl.blur(ctx, frame, name)  # warm-up: shaders compiled, textures pooled
        times = []
        for _ in range(runs):
            timed = bl.blur(ctx, frame, name)
            times.append(timed.total_ms)
            passes = {key: t.ms for key, t in timed.timings.items()}
            del timed
        rows.append(
            {
                "scene": scene_name,
                "method": name,
                "psnr": bl.metrics.psnr(reference.color, out.color),
                "ssim": bl.metrics.ssim(reference.color, out.color),
                "flip": bl.metrics.flip(reference.color, out.color),
                "ms": statistics.median(times),
                "passes": passes,
                "reference_samples": reference.samples,
            }
        )
    return rows


def markdown(table: pd.DataFrame) -> str:
    """One row per scene: PSNR / SSIM / FLIP per method, then the median ms per method."""
    methods = list(dict.fromkeys(table["method"]))
    lines = [
        "| scene | " + " | ".join(methods) + " |",
        "|---|" + "---|" * len(methods),
    ]
    for scene, rows in table.groupby("scene", sort=False):
        by = rows.set_index("method")
        cells = [
            f"{by.psnr[m]:.2f} / {by.ssim[m]:.3f} / {by.flip[m]:.3f}" if m in by.index else "–"
            for m in methods
        ]
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")
    medians = table.groupby("method", sort=False)[["psnr", "ms"]].median()
    lines.append(
        "| **median PSNR** | " + " | ".join(f"**{medians.psnr[m]:.2f}**" for m in methods) + " |"
    )
    lines.append(
        "| **median ms** | " + " | ".join(f"**{medians.ms[m]:.2f}**" for m in methods) + " |"
    )
    return "\n".join(lines) + "\n"


def pareto_chart(table: pd.DataFrame, renderer: str, clock: str, size):
    """Median ms against median PSNR over the scenes, one point per method, front marked."""
    medians = table.groupby("method", sort=False)[["psnr", "ms"]].median().reset_index()
    medians = medians.rename(columns={"ms": "total_ms"})
    medians = medians.assign(
        scene="median over scenes", renderer=renderer, clock=clock, width=size[0], height=size[1]
    )
    return bl.plots.pareto(medians, "median over scenes")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--scenes", default=None, help="comma-separated; default: all")
    parser.add_argument("--methods", default=None, help="comma-separated; default: all")
    parser.add_argument("--json", default=None)
    parser.add_argument("--markdown", default=None)
    parser.add_argument("--chart", default=None, help="PNG or SVG: median ms against PSNR")
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    scenes = (
        args.scenes.split(",") if args.scenes else bl.scenes.names() + bl.scenes.names("failure")
    )
    methods = args.methods.split(",") if args.methods else engine_methods()
    record = {**describe(ctx), "size": args.size, "runs": args.runs, "methods": methods}
    start = time.perf_counter()
    rows = []
    for scene_name in scenes:
        rows += measure(ctx, scene_name, size, args.runs, methods)
        print(f"{scene_name}: done", flush=True)
    record["seconds"] = round(time.perf_counter() - start, 1)
    table = pd.DataFrame(rows)
    print(f"\n{record['date']}  {record['renderer']}  {args.size}")
    for metric in ("psnr", "ssim", "flip", "ms"):
        print(f"\n{metric}")
        print(table.pivot(index="scene", columns="method", values=metric).round(3).to_string())
    if args.json:  # benchmarks/gpu.sh passes --json only: the table and chart go beside it
        args.markdown = args.markdown or args.json.removesuffix(".json") + ".md"
        args.chart = args.chart or args.json.removesuffix(".json") + "_pareto.png"
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(markdown(table))
    if args.chart:
        clock = bl.blur(ctx, ctx.render(bl.scenes.get(scenes[0]), (8, 8)), methods[0]).clock
        bl.plots.save(pareto_chart(table, record["renderer"], clock, size), args.chart)
    record["rows"] = rows
    save(args.json, record)


if __name__ == "__main__":
    main()
