"""Time per frame of the two hatching schemes (docs/spec.md §5), beside unhatched Lambert shading.

The scene is the notebook's: the teapot and the torus side by side, hatched with the default
TAM (256…16 texels). Reports the G-buffer pass alone (GL timer query on a GPU, glFinish + wall
clock on llvmpipe), median and min of --runs, after two warm-up renders (shader compilation).
With --measure it also runs tone reproduction (64 tones) and temporal coherence (32 frames).

    python benchmarks/hatching.py [--device gpu] [--size 1920x1080] [--runs 20] [--measure]
                                  [--json out.json]
"""

from __future__ import annotations

import argparse

import blurlab as bl
from blurlab.studies import hatching

from common import describe, save, summarize


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--measure", action="store_true")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    device = int(args.device) if args.device.isdigit() else args.device
    width, height = (int(v) for v in args.size.split("x"))

    ctx = bl.Context(device)
    tam = bl.tam.default_tam()
    record = {**describe(ctx), "size": f"{width}x{height}", "tam": tam.sizes, "passes": {}}
    for name in ("lambert", *bl.hatching.SCHEMES):
        s = hatching.pair_scene(None if name == "lambert" else name, tam)
        for _ in range(2):
            ctx.render(s, (width, height))
        times = []
        for _ in range(args.runs):
            frame = ctx.render(s, (width, height))
            times.append(frame.timings["gbuffer"].ms)
        record["passes"][name] = {**summarize(times), "clock": frame.timings["gbuffer"].clock}
    if args.measure:
        for scheme in bl.hatching.SCHEMES:
            tone = hatching.tone_reproduction(ctx, scheme, tam, steps=64, size=256)
            moving = hatching.temporal_coherence(ctx, scheme, tam, frames=32)
            still = hatching.temporal_coherence(ctx, scheme, tam, frames=32, moving_light=False)
            record[scheme] = {
                "tone_mean_abs_error": tone["mean_abs_error"],
                "distinguishable_steps": tone["distinguishable_steps"],
                "tone_measured": tone["measured"].round(4).tolist(),
                "pop_fraction_moving_light": moving["mean_pop_fraction"],
                "pop_fraction_still_light": still["mean_pop_fraction"],
                "reprojected_pop_fraction_moving_light": moving["mean_reprojected_pop_fraction"],
                "ink_change_moving_light": moving["mean_ink_change"],
            }
    save(args.json, record)
    print(f"\n{record['date']}  {record['renderer']}")
    print(f"teapot + torus, {width}x{height}, TAM {tam.sizes}, {args.runs} runs\n")
    print("| material | G-buffer pass median ms | min ms | clock |")
    print("|---|---|---|---|")
    for name, r in record["passes"].items():
        print(f"| {name} | {r['median_ms']:.3f} | {r['min_ms']:.3f} | {r['clock']} |")
    if args.measure:
        print(
            "\n| scheme | tone error | steps of 64 | pops, moving light | pops, still light "
            "| pops reprojected, moving light | mean abs ink change, moving light |"
        )
        print("|---|---|---|---|---|---|---|")
        for scheme in bl.hatching.SCHEMES:
            r = record[scheme]
            print(
                f"| {scheme} | {r['tone_mean_abs_error']:.4f} | {r['distinguishable_steps']} | "
                f"{r['pop_fraction_moving_light']:.4f} | {r['pop_fraction_still_light']:.4f} | "
                f"{r['reprojected_pop_fraction_moving_light']:.4f} | "
                f"{r['ink_change_moving_light']:.4f} |"
            )


if __name__ == "__main__":
    main()
