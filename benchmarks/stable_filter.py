"""The stable filter (reconstruct_guertin2014) against McGuire 2012, and each filter option,
on every failure scene and every built-in scene: error against the reference and time, in one
table; and the tile blockiness at k = 32 with and without the jittered tile lookup.

Every configuration runs at k = 20, S = 15 (the defaults) on the G-buffer at the shutter's
center. Error: PSNR and SSIM (both reduced on the GPU) against the scene's reference (N as the sweep
picks it). Time: median of --runs after one warm-up run, the sum of the passes by the context's
clock (GL timer queries on a GPU, glFinish + wall clock on llvmpipe). Blockiness:
bl.metrics.tile_border_error at k = 32, band 2 px.

    python benchmarks/stable_filter.py [--device gpu] [--size 1920x1080] [--runs 10]
        [--no-ssim] [--csv benchmarks/results/DATE-DEVICE-stable_filter.csv]
    bash benchmarks/gpu.sh "stable_filter --size 1920x1080 --runs 20"
"""

from __future__ import annotations

import argparse
import csv
import statistics
from pathlib import Path

import blurlab as bl
from blurlab.converged import default_reference_samples

from common import describe, open_context, save

FILTERS = ("reconstruct_mcguire2012", "reconstruct_guertin2014")
OPTIONS = {
    "": {},
    "jitter_tiles": {"jitter_tiles": 1},
    "adaptive_samples": {"adaptive_samples": 1},
    "early_exit=2": {"early_exit": 2.0},
}
BLOCKY_K = 32


def measure(ctx, frame, reference, configs, runs, ssim=True) -> list[dict]:
    """Time and error of each (method, params) in `configs`: one warm-up run each, then
    `runs` rounds in which every configuration runs once, so that a change of the machine's
    load (llvmpipe shares the CPU) touches all of them alike."""
    for method, params in configs:
        bl.blur(ctx, frame, method, **params)  # compile, and on llvmpipe JIT, before timing
    totals = [[] for _ in configs]
    for _ in range(runs):
        for i, (method, params) in enumerate(configs):
            result = bl.blur(ctx, frame, method, **params)
            totals[i].append(result.total_ms)
            clock = result.clock
            del result  # back to the pool: fresh textures cost GPU time on first use
    out = []
    for (method, params), times in zip(configs, totals, strict=True):
        result = bl.blur(ctx, frame, method, timed=False, **params)
        mse = bl.metrics.gpu_mse(ctx, result.textures["color"], reference.texture)
        out.append(
            {
                "total_ms": statistics.median(times),
                "clock": clock,
                "psnr": bl.metrics.psnr_from_mse(mse),
                "ssim": (
                    bl.metrics.gpu_ssim(ctx, result.textures["color"], reference.texture)
                    if ssim
                    else float("nan")
                ),
                "result": result,  # downloaded only where the blockiness needs its color
            }
        )
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="320x180")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--scenes", default=None, help="comma-separated (default: all)")
    parser.add_argument("--csv", default=None, help="the table (default: beside --json)")
    parser.add_argument("--no-ssim", action="store_true", help="skip SSIM")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "runs": args.runs, "rows": []}
    failure = bl.scenes.names("failure")
    names = args.scenes.split(",") if args.scenes else failure + bl.scenes.names()
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, medians of {args.runs} runs")
    print("\n| scene | method | options | k | PSNR dB | SSIM | ms | clock |")
    print("|---|---|---|---|---|---|---|---|")
    rows = record["rows"]
    for name in names:
        scene = bl.scenes.get(name)
        frame = ctx.render(scene, size)
        n = default_reference_samples(frame)
        reference = ctx.reference(scene, size, samples=n, progress=False)
        base = {
            "scene": name,
            "suite": "failure" if name in failure else "built-in",
            "reference_samples": n,
        }
        configs = [
            (method, label, 20, options) for method in FILTERS for label, options in OPTIONS.items()
        ] + [
            (method, label, BLOCKY_K, options)
            for method in FILTERS
            for label, options in (("", {}), ("jitter_tiles", {"jitter_tiles": 1}))
        ]
        measured = measure(
            ctx,
            frame,
            reference,
            [(c[0], {"k": c[2], **c[3]}) for c in configs],
            args.runs,
            ssim=not args.no_ssim,
        )
        for (method, label, k, _), m in zip(configs, measured, strict=True):
            row = {
                **base,
                "method": method,
                "options": label,
                "k": k,
                **{key: m[key] for key in ("psnr", "ssim", "total_ms", "clock")},
            }
            if k == BLOCKY_K:
                blocky = bl.metrics.tile_border_error(
                    reference.color, m["result"].color, BLOCKY_K, 2
                )
                row.update({f"tile_{key}": value for key, value in blocky.items()})
            rows.append(row)
            print(
                f"| {name} | {method} | {label or '—'} | {k} | {m['psnr']:.2f} | {m['ssim']:.4f} "
                f"| {m['total_ms']:.3f} | {m['clock']} |"
            )
    for row in rows:
        row.update(
            {
                "device": record["device"],
                "renderer": record["renderer"],
                "width": size[0],
                "height": size[1],
                "date": record["date"],
            }
        )
    summarize(rows, failure)
    path = args.csv or (str(Path(args.json).with_suffix(".csv")) if args.json else None)
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w", newline="") as f:
            writer = csv.DictWriter(f, sorted({key for row in rows for key in row}))
            writer.writeheader()
            writer.writerows(rows)
        print(f"\nwrote {path}")
    save(args.json, record)


def summarize(rows, failure) -> None:
    def pick(method, options, k=20, suite=None):
        return {
            r["scene"]: r
            for r in rows
            if r["method"] == method
            and r["options"] == options
            and r["k"] == k
            and (suite is None or r["suite"] == suite)
        }

    # The failure scenes where the run has any (the goal), else every scene run.
    suite = "failure" if any(r["suite"] == "failure" for r in rows) else None
    old = pick(FILTERS[0], "", suite=suite)
    print(
        "\n### Against reconstruct_mcguire2012 at k = 20, S = 15 "
        f"({'failure scenes' if suite else 'all scenes run'})\n"
    )
    print("| method | options | mean PSNR dB | PSNR > 2012 on | mean ms | ms / 2012 |")
    print("|---|---|---|---|---|---|")
    for method in FILTERS:
        for label in OPTIONS:
            mine = pick(method, label, suite=suite)
            wins = sum(mine[s]["psnr"] > old[s]["psnr"] + 1e-3 for s in mine)
            mean = statistics.mean(r["psnr"] for r in mine.values())
            ms = statistics.mean(r["total_ms"] for r in mine.values())
            ratio = statistics.median(mine[s]["total_ms"] / old[s]["total_ms"] for s in mine)
            print(
                f"| {method} | {label or '—'} | {mean:.2f} | {wins} of {len(mine)} "
                f"| {ms:.3f} | {ratio:.2f} |"
            )
    print(f"\n### Blockiness at k = {BLOCKY_K}: error at tile borders / inside tiles\n")
    print("| scene | method | level ratio | + jitter | seam ratio | + jitter |")
    print("|---|---|---|---|---|---|")
    for method in FILTERS:
        plain, jittered = pick(method, "", BLOCKY_K), pick(method, "jitter_tiles", BLOCKY_K)
        for scene in plain:
            a, b = plain[scene], jittered[scene]
            print(
                f"| {scene} | {method} | {a['tile_ratio']:.3f} | {b['tile_ratio']:.3f} "
                f"| {a['tile_step_ratio']:.3f} | {b['tile_step_ratio']:.3f} |"
            )


if __name__ == "__main__":
    main()
