"""Sweep throughput: evaluations per second of the reconstruction filter with the error
reduced on the GPU and only a scalar read back (what a parameter sweep does).

One evaluation = bl.blur(reconstruct_mcguire2012) on a G-buffer kept on the GPU + the GPU
squared-error reduction against the reference + reading back its partial sums (PSNR).
Parameters cycle through a grid of k and S so that no two consecutive evaluations are alike.
Wall clock over the whole loop; with --untimed the per-pass timer queries are off.

    python benchmarks/sweep_throughput.py [--device gpu] [--size 1920x1080] [--evaluations 2000]
"""

from __future__ import annotations

import argparse
import itertools
import time

import blurlab as bl
from blurlab import metrics

from common import describe, save


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--evaluations", type=int, default=200)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = bl.Context(int(args.device) if args.device.isdigit() else args.device)
    width, height = (int(v) for v in args.size.split("x"))
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, (width, height))
    reference = ctx.reference(scene, (width, height), samples=64, progress=False)
    grid = list(itertools.product([10, 20, 40], [5, 9, 15, 25]))
    record = {**describe(ctx), "size": args.size, "evaluations": args.evaluations, "modes": {}}
    print(
        f"\n{record['date']}  {record['renderer']}  {args.size}, {args.evaluations} evaluations\n"
    )
    print("| timing of passes | evaluations / s | ms per evaluation |\n|---|---|---|")
    for timed in (True, False):
        for k, s in grid[:2]:  # warm up
            bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=timed)
        start = time.perf_counter()
        for i in range(args.evaluations):
            k, s = grid[i % len(grid)]
            result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=timed)
            psnr = metrics.psnr_from_mse(
                metrics.gpu_mse(ctx, result.textures["color"], reference.texture)
            )
            del result
        elapsed = time.perf_counter() - start
        rate = args.evaluations / elapsed
        mode = "timer query per pass" if timed else "untimed"
        record["modes"][mode] = {"evaluations_per_s": rate, "last_psnr": psnr}
        print(f"| {mode} | {rate:.0f} | {1e3 / rate:.3f} |")
    save(args.json, record)


if __name__ == "__main__":
    main()
