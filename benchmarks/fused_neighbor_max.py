"""Issue 19, "fewer, fuller dispatches": NeighborMax in its own pass against NeighborMax in the
compute reconstruct pass's prologue (docs/spec.md §3.6), for McGuire 2012 and Guertin 2014 at
k = 20, S = 15 on one G-buffer of teapot_pass. Both ways run on the same textures, in turn
(rounds of separate, fused), so a drifting clock or a busy machine hits both alike; each
round's time covers the NeighborMax pass and the reconstruct pass, or the fused pass alone.
TileMax is the same either way and left out. Medians and minima over --rounds; GL timer
queries on a GPU, glFinish + wall clock on llvmpipe. The filters themselves keep NeighborMax a
pass of its own: fused measured slower on the H100 and on llvmpipe (docs/benchmarks.md).

    python benchmarks/fused_neighbor_max.py [--device software] [--size 640x360] [--rounds 15]
"""

from __future__ import annotations

import argparse
import statistics

import blurlab as bl
from blurlab.methods import guertin2014, mcguire2012
from blurlab.methods.core import choice_defines, pass_uniforms
from blurlab.methods.tile_filter import NEIGHBOR_MAX, variant_defines

from common import describe, open_context, save

FILTERS = {  # method: (its reconstruct Pass, whether its NeighborMax keeps direction)
    "reconstruct_mcguire2012": (mcguire2012.RECONSTRUCT, False),
    "reconstruct_guertin2014": (guertin2014.RECONSTRUCT, True),
}


def both_ways(ctx, frame, name: str) -> dict:
    """The two ways to run one filter's NeighborMax and reconstruct, as callables."""
    step, diagonal_reach = FILTERS[name]
    method = bl.method(name)
    result = bl.blur(ctx, frame, name, k=20, samples=15)
    defines = choice_defines(method.params, step.params) | variant_defines(result.params)
    uniforms = pass_uniforms(method.params, result.params, step.params)
    gbuffer = {"color": frame.color, "depth": frame.depth, "motion": frame.motion}
    gbuffer = {key: ctx.upload(value) for key, value in gbuffer.items()}
    tiles = ctx.upload(result.buffers["tile_max"])
    grid = ctx.empty(result.buffers["neighbor_max"].shape)
    color = ctx.empty(frame.color.shape[:2] + (4,))
    neighbor_max = ctx.shader_pass(NEIGHBOR_MAX.shader)
    reconstruct = ctx.shader_pass(step.shader, defines)
    fused = ctx.shader_pass(step.shader, {**defines, "FUSED_NEIGHBOR_MAX": 1})

    def separate():
        neighbor_max.run(
            {"tile_max": tiles}, {"neighbor_max": grid}, {"diagonal_reach": diagonal_reach}
        )
        reconstruct.run({**gbuffer, "neighbor_max": grid}, {"result": color}, uniforms)

    def folded():
        fused.run(
            {**gbuffer, "tile_max": tiles},
            {"result": color, "neighbor_max": grid},
            {**uniforms, "diagonal_reach": diagonal_reach},
        )

    return {"separate": separate, "fused": folded}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    frame = ctx.render(bl.scenes.teapot_pass(), size)
    record = {**describe(ctx), "size": args.size, "rounds": args.rounds, "filters": {}}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, {args.rounds} rounds")
    print(
        "\n| filter | separate, ms (median / min) | fused, ms (median / min) | fused / separate |"
    )
    print("|---|---|---|---|")
    for name in FILTERS:
        ways = both_ways(ctx, frame, name)
        samples = {way: [] for way in ways}
        for run in ways.values():  # compile and warm up
            run()
        for _ in range(args.rounds):
            for way, run in ways.items():
                with ctx.timer() as timing:
                    run()
                samples[way].append(timing.ms)
        stats = {
            w: {"median_ms": statistics.median(v), "min_ms": min(v)} for w, v in samples.items()
        }
        ratio = stats["fused"]["median_ms"] / stats["separate"]["median_ms"]
        record["filters"][name] = {**stats, "fused_over_separate": ratio}
        cells = " | ".join(f"{s['median_ms']:.4f} / {s['min_ms']:.4f}" for s in stats.values())
        print(f"| {name} | {cells} | {ratio:.2f} |")
    save(args.json, record)


if __name__ == "__main__":
    main()
