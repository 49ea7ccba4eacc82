"""The precision study of "Blurry things" (docs/spec.md §2): error of each motion storage format
against rg32f as the motion grows, measured on the GPU's encode/decode pass.

For each length L, 4096 vectors of length L at evenly spread directions (plus a small random
offset of angle) are stored in each format with maxlen = the diagonal of a 1920x1080 image, and
decoded. Prints a Markdown table of the mean and largest |decoded - M| in pixels, and of the
error relative to L.

    python benchmarks/motion_formats.py [--device auto] [--maxlen 2202.9]
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import blurlab as bl
from blurlab.render import stored_motion

from common import describe, open_context, save

LENGTHS = [0.1, 0.25, 0.5, 1, 2, 4, 8, 16, 32, 64]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--maxlen", type=float, default=math.hypot(1920, 1080))
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)

    rng = np.random.default_rng(0)
    angles = np.linspace(0, 2 * np.pi, 4096, endpoint=False) + rng.uniform(0, 1e-3, 4096)
    directions = np.stack([np.cos(angles), np.sin(angles)], -1)
    motion = np.concatenate([directions * length for length in LENGTHS]).astype(np.float32)
    motion = motion.reshape(len(LENGTHS), 4096, 2)  # one row of the "image" per length

    print(f"{describe(ctx)['date']}  {ctx.info()['renderer']}; maxlen = {args.maxlen:.1f} px\n")
    print("| |M| px | " + " | ".join(f"{f} mean / max px" for f in bl.MOTION_FORMATS[1:]) + " |")
    print("|---|" + "---|" * (len(bl.MOTION_FORMATS) - 1))
    results = {f: stored_motion(ctx, motion, f, args.maxlen) for f in bl.MOTION_FORMATS[1:]}
    table = []
    for row, length in enumerate(LENGTHS):
        cells = []
        for fmt in bl.MOTION_FORMATS[1:]:
            error = np.linalg.norm(results[fmt][row] - motion[row], axis=-1)
            cells.append(f"{error.mean():.3g} / {error.max():.3g}")
            table.append(
                {
                    "length": length,
                    "format": fmt,
                    "mean": float(error.mean()),
                    "max": float(error.max()),
                }
            )
        print(f"| {length} | " + " | ".join(cells) + " |")
    save(args.json, {**describe(ctx), "maxlen": args.maxlen, "errors": table})
    still = stored_motion(ctx, np.zeros((1, 1, 2), np.float32), "rgba8_offset", args.maxlen)
    print(f"\nrgba8_offset decodes zero motion as {still[0, 0].tolist()} px")


if __name__ == "__main__":
    main()
