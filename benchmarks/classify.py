"""Tile classification (Jimenez 2014) on a mostly still scene, and `steps` on the rotating fans.

Part 1: reconstruct_mcguire2012 with and without classify=True on `mostly_still` (a small card
sliding over a still room), the G-buffer kept on the GPU; per-pass medians of --runs runs
(the two configurations alternate, after two warm-ups each), the tiles in each class, and the
PSNR of each against the scene's reference. The issue's goal: >= 2x faster at 1920x1080 on
the GPU with the error within 0.1 dB.

Part 2: steps = 1, 2, 4 on fan and fast_fan: time (every pass, the extra G-buffers and the
averaging) and PSNR against the reference.

    python benchmarks/classify.py [--device gpu] [--size 1920x1080] [--runs 20]
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

import blurlab as bl
from blurlab.converged import default_reference_samples

from common import describe, open_context, save

FILTER = "reconstruct_mcguire2012"
SHARED = ("tile_max", "neighbor_max")  # passes both configurations run


def timed_runs(ctx, frame, configurations: dict, runs: int) -> dict:
    """Per-pass medians (ms) of each configuration, the configurations alternating."""
    for params in configurations.values():
        for _ in range(2):
            bl.blur(ctx, frame, FILTER, **params)
    samples = {label: [] for label in configurations}
    for _ in range(runs):
        for label, params in configurations.items():
            result = bl.blur(ctx, frame, FILTER, **params)
            samples[label].append({p: t.ms for p, t in result.timings.items()})
            clock = result.clock
            del result
    out = {}
    for label, rows in samples.items():
        passes = {p: statistics.median(r[p] for r in rows) for p in rows[0]}
        after = [sum(v for p, v in r.items() if p not in SHARED) for r in rows]
        out[label] = {
            "passes": passes,
            "total": statistics.median(sum(r.values()) for r in rows),
            "total_min": min(sum(r.values()) for r in rows),
            "after_tiles": statistics.median(after),
            "after_tiles_min": min(after),
            "clock": clock,
        }
    return out


def classification(ctx, scene_name, size, runs, k, samples, reference_samples) -> dict:
    scene = bl.scenes.get(scene_name)
    frame = ctx.render(scene, size)
    n = reference_samples or default_reference_samples(frame)
    reference = ctx.reference(scene, size, samples=n, progress=False)
    configurations = {
        "off": {"k": k, "samples": samples},
        "on": {"k": k, "samples": samples, "classify": True},
    }
    times = timed_runs(ctx, frame, configurations, runs)
    record = {
        "scene": scene_name,
        "size": list(size),
        "k": k,
        "samples": samples,
        "reference_samples": n,
        **times,
    }
    for label, params in configurations.items():
        result = bl.blur(ctx, frame, FILTER, timed=False, **params)
        record[label]["psnr"] = bl.metrics.psnr_from_mse(
            bl.metrics.gpu_mse(ctx, result.textures["color"], reference.texture)
        )
        if label == "on":
            classes = result.buffers["tile_class"].astype(int)
            record["tiles"] = dict(
                zip(
                    ("still", "uniform", "full"),
                    np.bincount(classes.ravel(), minlength=3).tolist(),
                    strict=True,
                )
            )
        del result
    on, off = record["on"], record["off"]
    record["speedup_total"] = off["total"] / on["total"]
    record["speedup_after_tiles"] = off["after_tiles"] / on["after_tiles"]
    record["speedup_total_min"] = off["total_min"] / on["total_min"]
    record["speedup_after_tiles_min"] = off["after_tiles_min"] / on["after_tiles_min"]
    record["psnr_change_db"] = on["psnr"] - off["psnr"]
    return record


def print_classification(r: dict) -> None:
    w, h = r["size"]
    print(
        f"\n### {r['scene']} {w}x{h}, k = {r['k']}, S = {r['samples']}, "
        f"reference N = {r['reference_samples']}; tiles {r['tiles']}\n"
    )
    passes = list(r["on"]["passes"])
    print("| classify | " + " | ".join(passes) + " | total ms | best total ms | PSNR dB |")
    print("|---" * (len(passes) + 4) + "|")
    for label in ("off", "on"):
        m = r[label]
        cells = [f"{m['passes'][p]:.4f}" if p in m["passes"] else "" for p in passes]
        print(
            f"| {label} | "
            + " | ".join(cells)
            + f" | {m['total']:.4f} | {m['total_min']:.4f} | {m['psnr']:.3f} |"
        )
    print(
        f"\nspeed-up, all passes: {r['speedup_total']:.2f}x; after TileMax/NeighborMax: "
        f"{r['speedup_after_tiles']:.2f}x; PSNR change {r['psnr_change_db']:+.3f} dB "
        f"(goal: >= 2x, within 0.1 dB); clock {r['on']['clock']}"
    )


def steps_study(ctx, size, runs, reference_samples) -> list[dict]:
    rows = []
    for scene_name in ("fan", "fast_fan"):
        scene = bl.scenes.get(scene_name)
        first = ctx.render(scene, size)
        n = reference_samples or default_reference_samples(first)
        reference = ctx.reference(scene, size, samples=n, progress=False)
        for steps in (1, 2, 4):
            frames = bl.render_steps(ctx, scene, FILTER, steps, size)
            bl.blur_steps(ctx, frames, FILTER)  # warm-up
            totals = []
            for _ in range(runs):
                result = bl.blur_steps(ctx, frames, FILTER)
                totals.append(result.total_ms)
                del result
            result = bl.blur_steps(ctx, frames, FILTER, timed=False)
            psnr = bl.metrics.psnr_from_mse(
                bl.metrics.gpu_mse(ctx, result.textures["color"], reference.texture)
            )
            rows.append(
                {
                    "scene": scene_name,
                    "steps": steps,
                    "total_ms": statistics.median(totals),
                    "psnr": psnr,
                    "reference_samples": n,
                }
            )
            del result, frames
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--k", type=int, default=20)
    parser.add_argument("--samples", type=int, default=15)
    parser.add_argument(
        "--scenes",
        default="mostly_still,teapot_pass",
        help="scenes of part 1 (the first is the goal's)",
    )
    parser.add_argument("--reference-samples", type=int, default=None)
    parser.add_argument("--no-steps", action="store_true", help="skip part 2")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "runs": args.runs, "classification": [], "steps": []}
    print(f"\n{record['date']}  {record['renderer']}  (medians of {args.runs} runs, ms)")
    for scene_name in args.scenes.split(","):
        r = classification(
            ctx, scene_name, size, args.runs, args.k, args.samples, args.reference_samples
        )
        record["classification"].append(r)
        print_classification(r)
    if not args.no_steps:
        record["steps"] = steps_study(ctx, size, args.runs, args.reference_samples)
        print("\n### steps, reconstruct_mcguire2012 (k = 20, S = 15)\n")
        print("| scene | steps | total ms (all passes, extra G-buffers, averaging) | PSNR dB |")
        print("|---|---|---|---|")
        for row in record["steps"]:
            print(
                f"| {row['scene']} | {row['steps']} | {row['total_ms']:.3f} | {row['psnr']:.2f} |"
            )
    save(args.json, record)


if __name__ == "__main__":
    main()
