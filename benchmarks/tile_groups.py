"""engine_eevee's tile flatten and dilation (docs/spec.md §17.2 steps 1-2), which
gather_coverage runs at its own sizes, in their two modes: one thread per tile against a work
group per tile (methods.eevee.tile_groups says which a device gets). Both modes run on the same
G-buffer of teapot_pass in turn (rounds of threads, groups), so a drifting clock or a busy
machine hits both alike; their outputs are checked to be the same bits. Then issue 17's time
goal: gather_coverage as bl.blur runs it (the mode tile_groups picks) against
reconstruct_guertin2014, in turn, each the sum of its passes; the goal is a ratio of at most
1.5. Medians and minima over --rounds; GL timer queries on a GPU, glFinish + wall clock on
llvmpipe.

    python benchmarks/tile_groups.py [--device software] [--size 1920x1080] [--rounds 15]
        [--json PATH]
"""

from __future__ import annotations

import argparse

import blurlab as bl
from blurlab.methods import coverage, eevee
from blurlab.twins import coverage as coverage_twin

from common import describe, open_context, save, summarize

MODES = {"threads": False, "groups": True}
PASSES = ("tile_flatten", "tile_dilate")
GOAL = 1.5  # issue 17: gather_coverage at most 1.5 x reconstruct_guertin2014's time


def tile_sizes(frame) -> dict:
    """Per method: (its parameter declarations, its values, tile size px, reach limit px)."""
    height = frame.color.shape[0]
    ours = bl.method("gather_coverage").defaults(frame)
    theirs = bl.method("engine_eevee").defaults(frame)
    return {
        "gather_coverage": (
            coverage.PARAMS,
            ours,
            coverage_twin.tile_size(height, ours["tile_percent"]),
            coverage_twin.max_blur_px(height, ours["max_blur"]),
        ),
        "engine_eevee": (eevee.PARAMS, theirs, theirs["tile_size"], theirs["max_blur"]),
    }


def run_mode(ctx, frame, case, group_per_tile: bool):
    """One flatten and dilation: (timings, (tiles, dilated) as bytes)."""
    params, values, tile_size, limit = case
    timings: dict = {}
    size = frame.color.shape[:2]
    _, tiles, dilated, _ = eevee.dilated_tiles(
        ctx, frame, timings, params, values, size, tile_size, limit, group_per_tile
    )
    return timings, tiles, dilated


def compare_modes(ctx, frame, rounds: int) -> dict:
    records = {}
    for name, case in tile_sizes(frame).items():
        outputs = {}
        for mode, groups in MODES.items():  # compile, warm up, keep the bits
            _, tiles, dilated = run_mode(ctx, frame, case, groups)
            outputs[mode] = tiles.download().tobytes() + dilated.download().tobytes()
            ctx.recycle(tiles, dilated)
        samples = {mode: {p: [] for p in PASSES} for mode in MODES}
        for _ in range(rounds):
            for mode, groups in MODES.items():
                timings, tiles, dilated = run_mode(ctx, frame, case, groups)
                ctx.recycle(tiles, dilated)
                for p in PASSES:
                    samples[mode][p].append(timings[p].ms)
        records[name] = {
            "tile_size": case[2],
            "reach_px": case[3],
            "same_bits": outputs["threads"] == outputs["groups"],
            **{m: {p: summarize(v) for p, v in by_pass.items()} for m, by_pass in samples.items()},
        }
        print(
            f"\n{name}: {case[2]} px tiles, reach {case[3]:g} px, same bits in both modes: "
            f"{records[name]['same_bits']}"
        )
        print(
            "| pass | threads, ms (median / min) | groups, ms (median / min) | groups / threads |"
        )
        print("|---|---|---|---|")
        for p in PASSES:
            a, b = records[name]["threads"][p], records[name]["groups"][p]
            print(
                f"| {p} | {a['median_ms']:.4f} / {a['min_ms']:.4f} | "
                f"{b['median_ms']:.4f} / {b['min_ms']:.4f} | "
                f"{b['median_ms'] / a['median_ms']:.2f} |"
            )
    return records


def time_goal(ctx, frame, rounds: int) -> dict:
    names = ("gather_coverage", "reconstruct_guertin2014")
    totals: dict = {name: [] for name in names}
    per_pass: dict = {name: {} for name in names}
    for name in names:
        bl.blur(ctx, frame, name)  # compile and warm up
    for _ in range(rounds):
        for name in names:
            result = bl.blur(ctx, frame, name)
            totals[name].append(result.total_ms)
            for p, timing in result.timings.items():
                per_pass[name].setdefault(p, []).append(timing.ms)
    record = {
        name: {
            "total": summarize(totals[name]),
            **{p: summarize(v) for p, v in per_pass[name].items()},
        }
        for name in names
    }
    ratio = record[names[0]]["total"]["median_ms"] / record[names[1]]["total"]["median_ms"]
    record["ratio"] = ratio
    record["goal_met"] = ratio <= GOAL
    record["groups_per_tile"] = eevee.tile_groups(ctx)
    print(f"\nissue 17's goal (tile passes with groups per tile: {record['groups_per_tile']}):")
    for name in names:
        passes = ", ".join(
            f"{p} {s['median_ms']:.4f}" for p, s in record[name].items() if p != "total"
        )
        print(f"  {name}: {record[name]['total']['median_ms']:.4f} ms median ({passes})")
    print(f"  ratio {ratio:.2f} (goal <= {GOAL}): {'met' if record['goal_met'] else 'not met'}")
    return record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    frame = ctx.render(bl.scenes.teapot_pass(), size, instant="center")
    record = {**describe(ctx), "size": args.size, "rounds": args.rounds}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, {args.rounds} rounds")
    record["modes"] = compare_modes(ctx, frame, args.rounds)
    record["goal"] = time_goal(ctx, frame, args.rounds)
    save(args.json, record)


if __name__ == "__main__":
    main()
