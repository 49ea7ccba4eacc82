"""Would gather_coverage's film filter work before the gather instead of after it? Issue 17's
lead: the film pass after the gather costs about 0.04 ms at 1080p on an H100 (0.6 x
reconstruct_guertin2014), and only with it does gather_coverage beat Blender's EEVEE on every
scene against the antialiased reference. Filtered before, the filter could ride on the taps'
own colour reads (each tap read through the film filter), with no pass of its own.

This measures accuracy only, on the NumPy twin: for each scene Blender can render, PSNR against
the antialiased reference of gather_coverage with its film filter after the gather (the method
as it is) and of the same gather over the film-filtered input colour, gather(film(c)), with
EEVEE's PSNR from the record of benchmarks/engines.py --peers eevee at the same size and N. No
timing: how the filter rides on the taps, and what that costs, is the GPU's question.

    python benchmarks/film_before_gather.py [--size 160x90] [--reference-samples 1024]
        [--samples 8 6 4] [--film-filter 0.5] [--eevee RECORD.json] [--json OUT.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import blurlab as bl
from blurlab.twins import coverage, film

from common import describe, open_context, save

EEVEE_RECORD = (
    Path(__file__).parent / "results" / "2026-11-24-llvmpipe-engines-eevee-samples-160x90.json"
)
EEVEE_ROW = "eevee (Blender)"
TWIN_PARAMS = ("tile_percent", "samples", "max_blur", "soft_z", "exposure", "seed")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="software")
    parser.add_argument("--size", default="160x90")
    parser.add_argument("--reference-samples", type=int, default=1024)
    parser.add_argument("--samples", type=int, nargs="+", default=[8, 6, 4])
    parser.add_argument("--film-filter", type=float, default=0.5)
    parser.add_argument("--eevee", default=str(EEVEE_RECORD))
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    eevee = json.loads(Path(args.eevee).read_text())
    if eevee["size"] != args.size or eevee["reference_samples"] != args.reference_samples:
        raise SystemExit(
            f"the EEVEE record is at {eevee['size']}, N = {eevee['reference_samples']}: "
            "run with the same --size and --reference-samples"
        )
    eevee_psnr = {  # the scenes Blender can render
        r["scene"]: r["psnr_aa"]
        for r in eevee["rows"]
        if r["method"] == EEVEE_ROW and r.get("psnr_aa") is not None
    }
    ctx = open_context(args.device)
    sigma = args.film_filter
    record = {**describe(ctx), "size": args.size, "film_filter": sigma, "rows": []}
    record.update(reference_samples=args.reference_samples, eevee_record=Path(args.eevee).name)
    print(
        f"\n{record['date']}  {record['renderer']}  {args.size}, antialiased references "
        f"N = {args.reference_samples}, film σ = {sigma}; PSNR dB\n"
    )
    columns = [f"{where} ({n} taps)" for n in args.samples for where in ("after", "before")]
    print("| scene | EEVEE | " + " | ".join(columns) + " |")
    print("|---|---|" + "---|" * len(columns))
    for name, eevee_db in eevee_psnr.items():
        scene = bl.scenes.get(name)
        frame = ctx.render(scene, size)
        reference = ctx.reference(
            scene, size, samples=args.reference_samples, antialias=True, progress=False
        ).color
        filtered = film.film_filter(frame.color, sigma)
        row = {"scene": name, "eevee": eevee_db}
        for n in args.samples:
            after = bl.blur(ctx, frame, "gather_coverage", samples=n, film_filter=sigma)
            params = {k: after.params[k] for k in TWIN_PARAMS}
            before = coverage.gather_coverage(
                filtered,
                frame.depth,
                frame.motion_prev,
                frame.motion_next,
                film_filter=0.0,
                **params,
            )
            row[f"after_{n}"] = bl.metrics.psnr(reference, after.color)
            row[f"before_{n}"] = bl.metrics.psnr(reference, before.astype(np.float32))
        record["rows"].append(row)
        cells = [row[f"{where}_{n}"] for n in args.samples for where in ("after", "before")]
        print(f"| {name} | {eevee_db:.2f} | " + " | ".join(f"{v:.2f}" for v in cells) + " |")
        save(args.json, record)
    print("\nscenes where it beats EEVEE:")
    for n in args.samples:
        for where in ("after", "before"):
            wins = [r["scene"] for r in record["rows"] if r[f"{where}_{n}"] > r["eevee"]]
            lost = {
                r["scene"]: round(r[f"{where}_{n}"] - r["eevee"], 2)
                for r in record["rows"]
                if r["scene"] not in wins
            }
            print(
                f"- film {where} the gather, {n} taps: {len(wins)} of {len(record['rows'])}"
                + (f"; lost {lost}" if lost else "")
            )


if __name__ == "__main__":
    main()
