"""Accuracy cost of packed filter inputs (issue 19, docs/spec.md §19): colour in RGBA16F and
motion + depth in one RGBA16F texture, packed on the GPU once per frame (packed_inputs=True),
against the textures as stored (RGBA32F, R32F, RG32F), on every built-in and failure scene; and
packed with the result written as half floats too (half_result=True: RGBA16F, not RGBA32F).

McGuire 2012 (k = 20, S = 15) and Guertin 2014 (defaults) blur each scene's G-buffer the three
ways; the table gives the PSNR of each against the converged reference and the changes from the
stored one, and FLIP of each. The bar:
|ΔPSNR| <= 0.05 dB on every scene. Also the packing pass's time per frame.

    python benchmarks/packed_inputs.py [--device auto] [--size 320x180] [--samples 128]
"""

from __future__ import annotations

import argparse

import blurlab as bl
from blurlab import metrics

from common import describe, open_context, save

FILTERS = {"reconstruct_mcguire2012": {"k": 20, "samples": 15}, "reconstruct_guertin2014": {}}
BAR_DB = 0.05


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
    print(
        "| scene | method | PSNR stored, dB | PSNR packed, dB | ΔdB | PSNR packed + half "
        "result, dB | ΔdB | FLIP stored | FLIP packed | FLIP packed + half result | packing, ms |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for scene_name in bl.scenes.names() + bl.scenes.names("failure"):
        scene = bl.scenes.get(scene_name)
        reference = ctx.reference(scene, size, samples=args.samples, progress=False).color
        for name, params in FILTERS.items():
            frame = ctx.render(scene, size, instant=bl.method_instant(name, params))
            sharp = bl.blur(ctx, frame, name, timed=False, **params).color
            stored = metrics.psnr(sharp, reference)
            out = bl.blur(ctx, frame, name, timed=False, packed_inputs=True, **params)
            packed = metrics.psnr(out.color, reference)
            both = bl.blur(
                ctx, frame, name, timed=False, packed_inputs=True, half_result=True, **params
            ).color.astype("float32")
            half = metrics.psnr(both, reference)
            # FLIP reacts to half-float steps far more than PSNR does (docs/benchmarks.md).
            flip_stored = metrics.flip(sharp, reference)
            flip_packed = metrics.flip(out.color, reference)
            flip_half = metrics.flip(both, reference)
            row = {
                "scene": scene_name,
                "method": name,
                "psnr_stored": stored,
                "psnr_packed": packed,
                "change_db": packed - stored,
                "psnr_packed_half_result": half,
                "change_half_result_db": half - stored,
                "flip_stored": flip_stored,
                "flip_packed": flip_packed,
                "flip_packed_half_result": flip_half,
                "pack_ms": frame.timings["pack_inputs"].ms,
            }
            record["rows"].append(row)
            print(
                f"| {scene_name} | {name} | {stored:.3f} | {packed:.3f} | "
                f"{row['change_db']:+.4f} | {half:.3f} | {row['change_half_result_db']:+.4f} | "
                f"{flip_stored:.5f} | {flip_packed:.5f} | {flip_half:.5f} | {row['pack_ms']:.3f} |"
            )
    worst = max(abs(r["change_db"]) for r in record["rows"])
    worst_half = max(abs(r["change_half_result_db"]) for r in record["rows"])
    record["largest_change_half_result_db"] = worst_half
    record["largest_change_db"] = worst
    verdict = "within" if worst <= BAR_DB else "outside"
    print(f"\nlargest |change| {worst:.4f} dB over {len(record['rows'])} rows: {verdict} the bar")
    verdict = "within" if worst_half <= BAR_DB else "outside"
    print(f"with the half-float result too: {worst_half:.4f} dB, {verdict} the bar")
    # What the half-float result alone costs: against the packed inputs' float32 result.
    alone = max(abs(r["psnr_packed_half_result"] - r["psnr_packed"]) for r in record["rows"])
    record["largest_change_half_result_over_packed_db"] = alone
    print(f"the half-float result alone (against packed): largest |change| {alone:.4f} dB")
    flip_up = [r["flip_packed_half_result"] - r["flip_packed"] for r in record["rows"]]
    record["flip_change_half_result"] = {"min": min(flip_up), "max": max(flip_up)}
    print(f"... and FLIP (against packed): {min(flip_up):+.5f} to {max(flip_up):+.5f}")
    packing_up = [r["flip_packed"] - r["flip_stored"] for r in record["rows"]]
    record["flip_change_packed"] = {"min": min(packing_up), "max": max(packing_up)}
    print(f"FLIP of packed against stored: {min(packing_up):+.5f} to {max(packing_up):+.5f}")
    save(args.json, record)


if __name__ == "__main__":
    main()
