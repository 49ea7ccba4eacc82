"""Blender EEVEE's own post-process motion blur (1 sample, 1 step, through blurlab.blender)
beside blurlab's filters on every built-in and failure scene that Blender can reproduce (issue
17): PSNR against blurlab's antialiased reference (EEVEE filters its pixels, as Cycles does)
and against the temporal one (the reference benchmarks/engines.py scores with). Scenes that
Blender cannot render as blurlab does are listed with the reason.

Needs the optional extra `blender` (bpy, Python 3.11); EEVEE runs on the GL device Blender finds.

With --film-filter σ, gather_coverage runs a second time with its Gaussian film filter of σ px
(docs/spec.md §17.6; 0.5 is EEVEE's at its default 1.5 px filter size), labelled as such: the
filtered image is for the antialiased reference, which EEVEE's film filter also aims at. The
record then also holds how closely that filter on blurlab's sharp frame matches EEVEE's image
where nothing moves (PSNR over the flat region of blurlab.blender.crosscheck.regions).

    python benchmarks/versus_eevee.py [--size 160x90] [--reference-samples 1024]
        [--methods a,b,...] [--film-filter 0.5] [--json PATH]
"""

from __future__ import annotations

import argparse
import statistics

import blurlab as bl
from blurlab.blender.crosscheck import psnr_in, regions
from blurlab.twins.film import film_filter

from common import describe, method_runs, open_context, save

METHODS = ("gather_coverage", "reconstruct_guertin2014", "engine_eevee", "engine_unity")
EEVEE = "EEVEE 1 sample, 1 step"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="160x90")
    parser.add_argument("--reference-samples", type=int, default=1024)
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--film-filter", type=float, default=0.0, help="σ, px; 0: no extra row")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    methods = args.methods.split(",")
    runs = method_runs(methods, args.film_filter)
    record = {**describe(ctx), "size": args.size, "reference_samples": args.reference_samples}
    record["refused"], record["scenes"] = {}, {}
    for name in bl.scenes.names() + bl.scenes.names("failure"):
        scene = bl.scenes.get(name)
        try:
            bl.blender.check_reproducible(scene)
        except ValueError as refusal:
            record["refused"][name] = str(refusal)
            print(f"{name}: refused: {refusal}", flush=True)
            continue
        n = args.reference_samples
        references = {
            "antialiased": ctx.reference(scene, size, samples=n, antialias=True, progress=False),
            "temporal": ctx.reference(scene, size, samples=n, progress=False),
        }
        eevee = bl.blender.render(scene, size, engine="EEVEE", samples=1, steps=1)
        frame = ctx.render(scene, size)
        images = {EEVEE: eevee.color}
        images.update({label: bl.blur(ctx, frame, m, **p).color for label, m, p in runs})
        entry = {"eevee_device": eevee.device}
        if args.film_filter > 0:
            film = args.film_filter
            flat = regions(ctx, scene, size, references["temporal"].color)["flat"]
            if flat.any():  # near_plane has no pixel that motion leaves alone
                entry["eevee_vs_film_filtered_sharp_flat_db"] = psnr_in(
                    eevee.color, film_filter(frame.color, film), flat
                )
        scores = {
            label: {k: bl.metrics.psnr(ref.color, image) for k, ref in references.items()}
            for label, image in images.items()
        }
        record["scenes"][name] = {"psnr": scores, **entry}
        print(name, {k: {r: round(v, 2) for r, v in s.items()} for k, s in scores.items()})
        print(name, {k: round(v, 2) for k, v in entry.items() if k != "eevee_device"})
    print(markdown(record, [EEVEE, *(label for label, _, _ in runs)]))
    save(args.json, record)


def markdown(record: dict, labels: list[str]) -> str:
    lines = []
    for ref in ("antialiased", "temporal"):
        lines += [
            "",
            f"PSNR (dB) against the {ref} reference, {record['size']}:",
            "",
            "| scene | " + " | ".join(labels) + " |",
            "|---|" + "---|" * len(labels),
        ]
        for name, s in record["scenes"].items():
            cells = [f"{s['psnr'][label][ref]:.2f}" for label in labels]
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        medians = [
            statistics.median(s["psnr"][label][ref] for s in record["scenes"].values())
            for label in labels
        ]
        lines.append("| **median** | " + " | ".join(f"**{m:.2f}**" for m in medians) + " |")
    lines += ["", "Refused: " + (", ".join(sorted(record["refused"])) or "none")]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
