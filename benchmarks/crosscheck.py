"""blurlab against Blender 5.0 (docs/crosscheck.md): geometry, references and methods checked
against Cycles, EEVEE as a peer, on three scenes of this script's own.

Needs the optional extra `blender` (bpy, Python 3.11). Cycles runs on the CPU; EEVEE and
blurlab on whatever GL device they find (llvmpipe on a machine without a GPU).

--methods limits the blurlab methods (default: every sweepable one); --config
METHOD:KEY=VALUE,... adds a row of a method with those parameters; --film-filter σ adds
gather_coverage with its Gaussian film filter of σ px (docs/spec.md §17.6), a row of its own:
Cycles filters its pixels (a 1 px box here), EEVEE too (its 1.5 px filter size).

    python benchmarks/crosscheck.py [--size 160x90] [--cycles-samples 2048]
        [--reference-samples 1024] [--scenes a,b] [--methods a,b] [--film-filter 0.5]
        [--config gather_coverage:samples=4 ...]
        [--json out.json] [--markdown out.md]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import blurlab as bl
from blurlab.blender.crosscheck import (
    SCENES,
    TRACKED,
    coverage_stats,
    iou,
    mask_scene,
    psnr_in,
    regions,
)
from blurlab.studies.sweep import sweep_methods

from common import add_config_argument, describe, method_runs, open_context, save


def progress_log(scene_name: str, started: float):
    return lambda *a: print(f"[{time.perf_counter() - started:6.0f} s] {scene_name}:", *a)


def method_rows(ctx, scene, size, references, runs: list[tuple[str, str, dict]]) -> list[dict]:
    """One row per (label, method, parameters) of `runs`."""
    rows = []
    for label, name, params in runs:
        frame = ctx.render(scene, size, instant=bl.method_instant(name, params))
        bl.blur(ctx, frame, name, **params)  # warm-up: compile, JIT
        times, color = [], None
        for _ in range(3):
            result = bl.blur(ctx, frame, name, **params)
            times.append(sum(t.ms for t in result.timings.values()))
            color = result.color
            del result
        rows.append(
            {
                "method": label,
                "time": f"{statistics.median(times):.3g} ms GPU passes ({ctx.info()['renderer']})",
                **{k: bl.metrics.psnr(ref, color) for k, ref in references.items()},
            }
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="160x90")
    parser.add_argument("--cycles-samples", type=int, default=2048)
    parser.add_argument("--reference-samples", type=int, default=1024)
    parser.add_argument("--instant-samples", type=int, default=512)
    parser.add_argument("--scenes", default=",".join(SCENES))
    parser.add_argument("--methods", default=None, help="comma-separated; default: sweepable")
    parser.add_argument("--film-filter", type=float, default=0.0, help="σ, px; 0: no extra row")
    add_config_argument(parser)
    parser.add_argument("--json", default=None)
    parser.add_argument("--markdown", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    n, spp = args.reference_samples, args.cycles_samples
    record = {**describe(ctx), "size": args.size, "cycles_samples": spp, "reference_samples": n}
    record["scenes"] = {}
    names = args.methods.split(",") if args.methods else sweep_methods()
    runs = method_runs(names, args.film_filter, args.config)
    started = time.perf_counter()
    for scene_name in args.scenes.split(","):
        scene = SCENES[scene_name]()
        tracked = mask_scene(scene, TRACKED[scene_name])
        out = record["scenes"][scene_name] = {}
        log = progress_log(scene_name, started)
        # 1. Geometry without blur at shutter open and close.
        for instant in scene.shutter:
            cycles = bl.blender.render(tracked, size, samples=args.instant_samples, instant=instant)
            ours = ctx.reference(
                tracked, size, (instant, instant), samples=256, antialias=True, progress=False
            )
            a, b = cycles.color[..., 0], ours.color[..., 0]
            overlap = iou(a, b)
            shift = np.subtract(coverage_stats(a)["centroid"], coverage_stats(b)["centroid"])
            out[f"instant_{instant:g}"] = {"iou": overlap, "centroid_shift_px": shift.tolist()}
            log(f"t={instant:g} IoU {overlap:.4f}, centroid shift {shift.round(4)} px")
        # 2. References against Cycles, by region.
        cycles = bl.blender.render(scene, size, samples=spp, seed=0)
        cycles_again = bl.blender.render(scene, size, samples=spp, seed=1)
        antialiased = ctx.reference(scene, size, samples=n, antialias=True, progress=False).color
        # The same reference over the part of the shutter Cycles spans (spec §16.4).
        spanned = bl.blender.cycles_shutter(scene.shutter)
        matched = ctx.reference(
            scene, size, spanned, samples=n, antialias=True, progress=False
        ).color
        temporal = ctx.reference(scene, size, samples=n, progress=False).color
        where = regions(ctx, scene, size, temporal)
        where["all"] = np.ones(temporal.shape[:2], bool)
        out["pixels"] = {k: int(v.sum()) for k, v in where.items()}
        out["cycles"] = {
            "settings": cycles.settings,
            "wall_s": cycles.wall_s,
            "render_s": cycles.render_s,
            "device": cycles.device,
        }
        for label, image in (
            ("antialiased", antialiased),
            ("antialiased_cycles_shutter", matched),
            ("temporal", temporal),
            ("cycles_seed_1", cycles_again.color),
        ):
            out[f"{label}_vs_cycles_db"] = {
                k: psnr_in(image, cycles.color, v) for k, v in where.items() if v.any()
            }
            log(label, {k: round(v, 2) for k, v in out[f"{label}_vs_cycles_db"].items()})
        # 3. The blurred object's integrated area and centroid (timing).
        cycles_blur = bl.blender.render(tracked, size, samples=spp)
        c = coverage_stats(cycles_blur.color[..., 0])
        out["blurred_object"] = {"cycles": c}
        for label, interval in (("antialiased", scene.shutter), ("cycles_shutter", spanned)):
            ours = ctx.reference(tracked, size, interval, samples=n, antialias=True, progress=False)
            o = coverage_stats(ours.color[..., 0])
            out["blurred_object"][label] = {
                **o,
                "centroid_shift_px": np.subtract(c["centroid"], o["centroid"]).tolist(),
                "area_ratio": o["area"] / c["area"],
            }
        log("blurred object", out["blurred_object"])
        # 4. Every method, EEVEE 1 sample / 1 step and EEVEE's default, against all three.
        references = {"cycles": cycles.color, "antialiased": antialiased, "temporal": temporal}
        rows = method_rows(ctx, scene, size, references, runs)
        for label, samples, steps in (("EEVEE 1 sample, 1 step", 1, 1), ("EEVEE default", 64, 1)):
            eevee = bl.blender.render(scene, size, engine="EEVEE", samples=samples, steps=steps)
            rows.append(
                {
                    "method": label,
                    "time": f"{eevee.wall_s:.1f} s Blender wall ({eevee.render_s:.1f} s render), "
                    f"{eevee.device}",
                    **{k: bl.metrics.psnr(ref, eevee.color) for k, ref in references.items()},
                }
            )
        rows.append(
            {
                "method": f"antialiased reference N={n}",
                "time": "",
                **{k: bl.metrics.psnr(r, antialiased) for k, r in references.items()},
            }
        )
        rows.append(
            {
                "method": f"Cycles {spp} spp, seed 1",
                "time": f"{cycles_again.wall_s:.1f} s Blender wall, {cycles_again.device}",
                **{k: bl.metrics.psnr(r, cycles_again.color) for k, r in references.items()},
            }
        )
        out["methods"] = rows
        log("methods done")
    save(args.json, record)
    text = markdown(record)
    print(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)


def markdown(record: dict) -> str:
    lines = [
        f"{record['date']} · blurlab on {record['renderer']} · Cycles on the CPU · "
        f"{record['size']} · Cycles {record['cycles_samples']} spp · references "
        f"N = {record['reference_samples']}",
        "",
        "| scene | IoU open | IoU close | centroid shift open (px) | centroid shift close (px) |",
        "|---|---|---|---|---|",
    ]
    scenes = record["scenes"]
    for name, s in scenes.items():
        (o, c) = (s[k] for k in sorted(k for k in s if k.startswith("instant_")))
        lines.append(
            f"| {name} | {o['iou']:.4f} | {c['iou']:.4f} | "
            f"{np.round(o['centroid_shift_px'], 3).tolist()} | "
            f"{np.round(c['centroid_shift_px'], 3).tolist()} |"
        )
    lines += [
        "",
        "PSNR (dB) against Cycles, by region (pixels in each):",
        "",
        "| scene | image | all | still edges | moving | flat |",
        "|---|---|---|---|---|---|",
    ]
    for name, s in scenes.items():
        for label in ("antialiased", "antialiased_cycles_shutter", "temporal", "cycles_seed_1"):
            v = s[f"{label}_vs_cycles_db"]
            cells = [f"{v[k]:.1f}" if k in v else "—" for k in ("all", "still_edges", "moving")]
            cells.append(f"{v['flat']:.1f}" if "flat" in v else "—")
            lines.append(f"| {name} | {label} | " + " | ".join(cells) + " |")
        p = s["pixels"]
        lines.append(
            f"| {name} | pixels | {p['all']} | {p['still_edges']} | {p['moving']} | {p['flat']} |"
        )
    lines += [
        "",
        "| scene | shutter of the AA reference | area Cycles | area blurlab AA | "
        "centroid shift (px) |",
        "|---|---|---|---|---|",
    ]
    for name, s in scenes.items():
        b = s["blurred_object"]
        for label in ("antialiased", "cycles_shutter"):
            lines.append(
                f"| {name} | {'nominal' if label == 'antialiased' else 'the span Cycles samples'} "
                f"| {b['cycles']['area']:.2f} | {b[label]['area']:.2f} | "
                f"{np.round(b[label]['centroid_shift_px'], 4).tolist()} |"
            )
    for name, s in scenes.items():
        lines += [
            "",
            f"**{name}**: PSNR (dB) against Cycles, the antialiased and the temporal reference",
            "",
            "| method | vs Cycles | vs antialiased | vs temporal | time |",
            "|---|---|---|---|---|",
        ]
        for r in s["methods"]:
            lines.append(
                f"| {r['method']} | {r['cycles']:.2f} | {r['antialiased']:.2f} | "
                f"{r['temporal']:.2f} | {r['time']} |"
            )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
