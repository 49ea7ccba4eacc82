"""`steps` = 1, 2, 4 (docs/classify_and_steps.md) on the rotating fans: time of
reconstruct_mcguire2012 over all steps (every pass, the extra G-buffers and the averaging) and
PSNR against the reference.

The tile classification this benchmark also measured until it was removed (its record:
benchmarks/results/2026-11-23-*-classify.json; the script as it was: git show
aa22977:benchmarks/classify.py) is written up in docs/classify_and_steps.md.

    python benchmarks/steps.py [--device gpu] [--size 1920x1080] [--runs 20]
"""

from __future__ import annotations

import argparse
import statistics

import blurlab as bl
from blurlab.converged import default_reference_samples

from common import describe, open_context, save

FILTER = "reconstruct_mcguire2012"


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
    parser.add_argument("--reference-samples", type=int, default=None)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "runs": args.runs}
    print(f"\n{record['date']}  {record['renderer']}  (medians of {args.runs} runs, ms)")
    record["steps"] = steps_study(ctx, size, args.runs, args.reference_samples)
    print("\n### steps, reconstruct_mcguire2012 (k = 20, S = 15)\n")
    print("| scene | steps | total ms (all passes, extra G-buffers, averaging) | PSNR dB |")
    print("|---|---|---|---|")
    for row in record["steps"]:
        print(f"| {row['scene']} | {row['steps']} | {row['total_ms']:.3f} | {row['psnr']:.2f} |")
    save(args.json, record)


if __name__ == "__main__":
    main()
