"""Accuracy cost of packed filter inputs (issue 19): colour in RGBA16F and motion + depth in one
half-float texture (RG16F motion and R16F depth: 8 B per pixel with colour's 8 B against the
28 B stored today), on every built-in and failure scene.

Each scene's G-buffer is rounded to half floats exactly as those textures would hold it
(round to nearest even, as GL converts float32 to float16), and McGuire 2012 (k = 20, S = 15)
and Guertin 2014 (defaults) blur both versions; the table gives the PSNR of each against the
converged reference and the change. The bar: |ΔPSNR| <= 0.05 dB on every scene.

    python benchmarks/packed_inputs.py [--device auto] [--size 320x180] [--samples 128]
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

import blurlab as bl
from blurlab import metrics

from common import describe, open_context, save

FILTERS = {"reconstruct_mcguire2012": {"k": 20, "samples": 15}, "reconstruct_guertin2014": {}}
BAR_DB = 0.05


def half(array: np.ndarray) -> np.ndarray:
    """float32 -> float16 -> float32: what a half-float texture stores and a shader reads."""
    return np.asarray(array, np.float32).astype(np.float16).astype(np.float32)


# Which inputs go to half floats: both packed textures, and each alone.
VARIANTS = {
    "packed": ("color", "depth", "motion"),
    "colour RGBA16F": ("color",),
    "motion + depth RGBA16F": ("depth", "motion"),
}


def packed(frame: bl.Frame, parts) -> bl.Frame:
    """A copy of `frame` with `parts` as half floats; no GPU copies (uploaded on use)."""
    rounded = {part: half(getattr(frame, part)) for part in parts}
    return dataclasses.replace(frame, **rounded, textures={}, timings={})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="320x180")
    parser.add_argument("--samples", type=int, default=128, help="reference sub-frames")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "reference_samples": args.samples, "rows": []}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, reference N = {args.samples}\n")
    print("| scene | method | PSNR as stored, dB | " + " | ".join(f"{v}, ΔdB" for v in VARIANTS))
    print("|---|---|---|" + "---|" * len(VARIANTS))
    for scene_name in bl.scenes.names() + bl.scenes.names("failure"):
        scene = bl.scenes.get(scene_name)
        reference = ctx.reference(scene, size, samples=args.samples, progress=False).color
        for name, params in FILTERS.items():
            frame = ctx.render(scene, size, instant=bl.method_instant(name, params))
            result = bl.blur(ctx, frame, name, timed=False, **params)
            stored = metrics.psnr(result.color, reference)
            # soft_z defaults to 1 % of the frame's depth range: the packed frames keep the
            # stored frame's value, so only the inputs' precision changes.
            soft_z = result.params["soft_z"]
            row = {"scene": scene_name, "method": name, "psnr_stored": stored}
            for variant, parts in VARIANTS.items():
                out = bl.blur(ctx, packed(frame, parts), name, timed=False, soft_z=soft_z, **params)
                row[variant] = metrics.psnr(out.color, reference) - stored
            record["rows"].append(row)
            changes = " | ".join(f"{row[v]:+.4f}" for v in VARIANTS)
            print(f"| {scene_name} | {name} | {stored:.3f} | {changes} |")
    for variant in VARIANTS:
        worst = max(abs(r[variant]) for r in record["rows"])
        record[f"largest_change_db {variant}"] = worst
        verdict = "within" if worst <= BAR_DB else "outside"
        print(f"{variant}: largest |change| {worst:.4f} dB, {verdict} the {BAR_DB} dB bar")
    save(args.json, record)


if __name__ == "__main__":
    main()
