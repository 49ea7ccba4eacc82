"""Reference sub-frames (issue 19, item "reference without per-sub-frame CPU round trips"):
wall clock of ctx.reference per sub-frame, beside the GPU time it reports per sub-frame
(ms_per_subframe: G-buffer pass + accumulation), and the same loop as it was before issue 19,
which read both timers of each sub-frame at once (a wait for the GPU each), rebuilt here from
the same pieces so that both run on one build. ctx.reference now reads all its timers after the
last sub-frame (Context.deferred_timers). Rounds alternate the two; medians.

    python benchmarks/reference_loop.py [--device gpu] [--size 1920x1080] [--samples 256]
"""

from __future__ import annotations

import argparse
import statistics
import time

import blurlab as bl
from blurlab.converged import accumulate
from blurlab.render import render_targets
from blurlab.twins.accumulation import sample_times

from common import describe, open_context, save


def waiting_reference(ctx, scene, size, samples: int) -> float:
    """The reference loop as it was before issue 19: each sub-frame's two timers read at once.
    Returns the summed GPU ms per sub-frame."""
    total = ctx.pooled((size[1], size[0], 4))
    total.clear()
    elapsed = 0.0
    for t in sample_times(scene.shutter, samples, True, 0):
        targets, _, timing = render_targets(ctx, scene, size, scene.shutter, float(t))
        with ctx.timer() as add:
            accumulate(ctx, targets["color"], total, 1.0 / samples)
        ctx.recycle(*targets.values())
        elapsed += timing.ms + add.ms
    ctx.recycle(total)
    return elapsed / samples


def wall_us(ctx, fn, samples: int) -> float:
    ctx.finish()
    start = time.perf_counter()
    fn()
    ctx.finish()
    return 1e6 * (time.perf_counter() - start) / samples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--scenes", default="teapot_pass,vehicle")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "samples": args.samples, "scenes": {}}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, N = {args.samples}")
    print(
        "\n| scene | before: wall µs per sub-frame | now: wall µs per sub-frame |"
        " GPU clock µs per sub-frame |"
    )
    print("|---|---|---|---|")
    for name in args.scenes.split(","):
        scene = bl.scenes.get(name)
        ctx.reference(scene, size, samples=4, progress=False)  # warm-up: programs, meshes
        before, now, gpus = [], [], []
        for _ in range(args.runs):

            def waiting(scene=scene):
                waiting_reference(ctx, scene, size, args.samples)

            def deferred(scene=scene, kept=gpus):
                reference = ctx.reference(scene, size, samples=args.samples, progress=False)
                kept.append(1e3 * reference.ms_per_subframe)

            before.append(wall_us(ctx, waiting, args.samples))
            now.append(wall_us(ctx, deferred, args.samples))
        row = {
            "before_wall_us_per_subframe": statistics.median(before),
            "wall_us_per_subframe": statistics.median(now),
            "gpu_us_per_subframe": statistics.median(gpus),
        }
        record["scenes"][name] = row
        print(
            f"| {name} | {row['before_wall_us_per_subframe']:.1f} | "
            f"{row['wall_us_per_subframe']:.1f} | {row['gpu_us_per_subframe']:.1f} |"
        )
    save(args.json, record)


if __name__ == "__main__":
    main()
