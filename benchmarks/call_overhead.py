"""What a Python call of bl.blur costs beyond its GPU work (issue 19, item "per-call overhead"),
with recorded dispatch plans (blurlab.methods.plans) and without them (plans.disabled(), the
ordinary path: parameter validation, uniform dicts, program and unit lookups pass by pass).

For each filter and size: wall clock per untimed call in a loop finished once (as a sweep makes
them); the Python part alone (the same loop with the GL calls replaced by no-ops: the Python
wrapper's ShaderPass.run on the ordinary path, DispatchPlan.run on the planned one); the one C++
replay call alone (binds, uniforms, dispatches and, on llvmpipe, whose dispatches run on the CPU,
their work); the GPU time of the passes by the context's clock; and per sweep evaluation (blur +
gpu_mse_ssim, parameters cycling through k and S). The Python part alone is CPU time of
this process; the rest wall clock. Rounds alternate the two paths so that a busy machine slows
both alike; the least of the rounds is reported (the least disturbed), the median in the JSON.

    python benchmarks/call_overhead.py [--device gpu] [--sizes 16x16,160x90,1920x1080]
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import statistics
import time

import blurlab as bl
from blurlab import _core, metrics
from blurlab.context import ShaderPass
from blurlab.methods import plans

from common import describe, open_context, save

FILTERS = {
    "reconstruct_mcguire2012": {"k": 20, "samples": 15},
    "reconstruct_guertin2014": {},
}
GRID = list(itertools.product([10, 20, 40], [5, 9, 15, 25]))
# The Python part alone is timed by this process's CPU time: on a shared machine the wall
# clock also counts the time other processes held the cores.
CPU = time.process_time


def per_call_us(ctx, fn, calls: int, clock=time.perf_counter) -> float:
    ctx.finish()
    start = clock()
    for i in range(calls):
        fn(i)
    ctx.finish()
    return 1e6 * (clock() - start) / calls


def gpu_us(ctx, frame, name, params, runs: int) -> float:
    """Median over runs of the summed pass times of a timed call."""
    totals = []
    for _ in range(runs):
        result = bl.blur(ctx, frame, name, **params)
        totals.append(1e3 * result.total_ms)
        del result
    return statistics.median(totals)


def replay_us(ctx, frame, name, params, calls: int) -> float:
    """The C++ replay call alone, on the textures a replayed call hands it."""
    result = bl.blur(ctx, frame, name, timed=False, **params)
    key = next(k for k, p in frame.plans.items() if p is not None and p.values == result.params)
    plan = frame.plans[key]
    textures = [t.native for _, t in plan.inputs]
    textures += [result.textures[name].native for name, _, _ in plan.outputs]
    return per_call_us(ctx, lambda i: plan.core.run(textures), calls)


@contextlib.contextmanager
def without_gl(owner, attribute: str):
    """`owner.attribute` (a method that issues GL work) as a no-op inside the block."""
    original = getattr(owner, attribute)
    setattr(owner, attribute, lambda *args, **kwargs: None)
    try:
        yield
    finally:
        setattr(owner, attribute, original)


def least_and_median(samples: dict) -> dict:
    row = {k: min(v) for k, v in samples.items()}
    row.update({f"{k}_median": statistics.median(v) for k, v in samples.items()})
    return row


def measure(ctx, frame, reference, calls: int, rounds: int) -> dict:
    out = {}
    for name, params in FILTERS.items():

        def call(i, name=name, params=params):
            bl.blur(ctx, frame, name, timed=False, **params)

        keys = ("ordinary", "planned", "python_ordinary", "python_planned", "replay_call")
        samples = {key: [] for key in keys}
        for _ in range(rounds):
            with plans.disabled():
                call(0)
                samples["ordinary"].append(per_call_us(ctx, call, calls))
                with without_gl(ShaderPass, "run"):
                    samples["python_ordinary"].append(per_call_us(ctx, call, calls, CPU))
            call(0)
            call(0)
            samples["planned"].append(per_call_us(ctx, call, calls))
            with without_gl(_core.DispatchPlan, "run"):
                samples["python_planned"].append(per_call_us(ctx, call, calls, CPU))
            samples["replay_call"].append(replay_us(ctx, frame, name, params, calls))
        row = least_and_median(samples)
        row["gpu"] = gpu_us(ctx, frame, name, params, max(calls // 4, 5))
        out[name] = row

    def evaluate(i):
        k, s = GRID[i % len(GRID)]
        color = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=False)
        color = color.textures["color"]
        metrics.gpu_mse_ssim(ctx, reference.texture, color)  # PSNR and SSIM, as sweeps do

    sweep = {"ordinary": [], "planned": []}
    for _ in range(rounds):
        with plans.disabled():
            sweep["ordinary"].append(per_call_us(ctx, evaluate, calls))
        for i in range(len(GRID)):
            evaluate(i)
        sweep["planned"].append(per_call_us(ctx, evaluate, calls))
    out["sweep_evaluation"] = least_and_median(sweep)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--sizes", default="16x16,160x90")
    parser.add_argument("--calls", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    record = {**describe(ctx), "calls": args.calls, "rounds": args.rounds, "sizes": {}}
    print(f"\n{record['date']}  {record['renderer']}, least of {args.rounds} rounds")
    print(
        "\n| size | method | ordinary, µs/call | planned, µs/call | Python alone, ordinary"
        " → planned, CPU µs | C++ replay alone, µs | GPU clock, µs |"
    )
    print("|---|---|---|---|---|---|---|")
    scene = bl.scenes.teapot_pass()
    for text in args.sizes.split(","):
        size = tuple(int(v) for v in text.split("x"))
        frame = ctx.render(scene, size)
        reference = ctx.reference(scene, size, samples=16, progress=False)
        rows = measure(ctx, frame, reference, args.calls, args.rounds)
        record["sizes"][text] = rows
        for name, row in rows.items():
            if name == "sweep_evaluation":
                continue
            print(
                f"| {text} | {name} | {row['ordinary']:.1f} | {row['planned']:.1f} | "
                f"{row['python_ordinary']:.1f} → {row['python_planned']:.1f} | "
                f"{row['replay_call']:.1f} | {row['gpu']:.1f} |"
            )
        sweep = rows["sweep_evaluation"]
        print(
            f"| {text} | sweep evaluation (blur + gpu_mse_ssim) | {sweep['ordinary']:.1f} "
            f"| {sweep['planned']:.1f} | | | |"
        )
    save(args.json, record)


if __name__ == "__main__":
    main()
