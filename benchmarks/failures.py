"""The failure-case table: every single-frame method on every failure scene (bl.failures).

Error against the reference (PSNR, SSIM), NaN/Inf, colors outside the input range, flicker
over an animation of --frames frames, and the filters' sensitivity to k and soft_z. Writes the
table as CSV (--csv) and, for benchmarks/gpu.sh, as JSON with the device that made it.

    python benchmarks/failures.py [--device gpu] [--size 320x180] [--frames 16] [--csv PATH]
        [--images FOLDER]
"""

from __future__ import annotations

import argparse
import json
import time

import blurlab as bl
from blurlab import failures

from common import describe, open_context, save


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="320x180")
    parser.add_argument("--frames", type=int, default=16)
    parser.add_argument("--csv", default=None)
    parser.add_argument("--json", default=None)
    parser.add_argument("--images", default=None, help="folder for one gallery PNG a scene")
    args = parser.parse_args()
    ctx = open_context(args.device)
    width, height = (int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "frames": args.frames}
    start = time.perf_counter()
    table = failures.evaluate(ctx, size=(width, height), frames=args.frames)
    record["seconds"] = round(time.perf_counter() - start, 1)
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, {args.frames} frames")
    print(table.pivot(index="scene", columns="method", values="psnr").round(1).to_string())
    if args.csv:
        table.to_csv(args.csv, index=False)
    if args.images:
        for name in bl.scenes.names("failure"):
            bl.plots.save(failures.gallery(ctx, name, (width, height)), f"{args.images}/{name}.png")
    record["rows"] = json.loads(table.to_json(orient="records"))
    save(args.json, record)


if __name__ == "__main__":
    main()
