"""Sweep throughput: evaluations per second of the reconstruction filter with the error
reduced on the GPU and only a scalar read back (what a parameter sweep does).

One evaluation = bl.blur(reconstruct_mcguire2012) on a G-buffer kept on the GPU + the GPU
squared-error reduction against the reference + reading back its partial sums (PSNR).
Parameters cycle through a grid of k and S so that no two consecutive evaluations are alike.
Wall clock over the whole loop, with and without per-pass timer queries, and untimed with SSIM
also reduced on the GPU (metrics.gpu_mse_ssim: PSNR and SSIM from one pass) as sweeps do.

Then SSIM alone, median of --ssim-repeats calls on one blurred image: metrics.ssim in NumPy
(after downloading both images, as sweeps did before) against metrics.gpu_ssim.

    python benchmarks/sweep_throughput.py [--device gpu] [--size 1920x1080] [--evaluations 2000]
"""

from __future__ import annotations

import argparse
import itertools
import time

import blurlab as bl
from blurlab import metrics

from common import describe, open_context, save, summarize


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--evaluations", type=int, default=200)
    parser.add_argument("--ssim-repeats", type=int, default=10)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
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
    for timed, ssim in ((True, False), (False, False), (False, True)):
        for k, s in grid[:2]:  # warm up
            bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=timed)
        start = time.perf_counter()
        for i in range(args.evaluations):
            k, s = grid[i % len(grid)]
            result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=timed)
            color = result.textures["color"]
            if ssim:  # both from one pass, as sweeps do
                mse, _ = metrics.gpu_mse_ssim(ctx, reference.texture, color)
            else:
                mse = metrics.gpu_mse(ctx, color, reference.texture)
            psnr = metrics.psnr_from_mse(mse)
            del result, color
        elapsed = time.perf_counter() - start
        rate = args.evaluations / elapsed
        mode = "timer query per pass" if timed else "untimed"
        mode += ", PSNR and SSIM on the GPU" if ssim else ""
        record["modes"][mode] = {"evaluations_per_s": rate, "last_psnr": psnr}
        print(f"| {mode} | {rate:.0f} | {1e3 / rate:.3f} |")
    record["ssim"] = time_ssim(ctx, frame, reference, args.ssim_repeats)
    save(args.json, record)


def time_ssim(ctx, frame, reference, repeats: int) -> dict:
    """SSIM of one blurred image against the reference: NumPy (with the downloads it needs)
    against the GPU reduction; milliseconds per call, and the two values."""
    color = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False).textures["color"]
    ways = {
        "NumPy metrics.ssim + downloads": lambda: metrics.ssim(
            reference.texture.download(), color.download()
        ),
        "GPU metrics.gpu_ssim": lambda: metrics.gpu_ssim(ctx, reference.texture, color),
    }
    record = {}
    print("\n| SSIM of one evaluation | median ms | min ms | value |\n|---|---|---|---|")
    for way, ssim in ways.items():
        value = ssim()  # warm up: compiles the shader, JITs on llvmpipe
        samples = []
        for _ in range(repeats):
            start = time.perf_counter()
            ssim()
            samples.append(1e3 * (time.perf_counter() - start))
        record[way] = {**summarize(samples), "ssim": value}
        stats = record[way]
        print(f"| {way} | {stats['median_ms']:.2f} | {stats['min_ms']:.2f} | {value:.7f} |")
    return record


if __name__ == "__main__":
    main()
