"""Timing helpers every benchmark shares: spin-up, per-pass medians, calls back to back, wall
clocks, and the method rows a benchmark's `config` parameter adds."""

from __future__ import annotations

import statistics
import time

from blurlab.methods import blur, method, methods
from blurlab.studies.sweep import sweep_methods

# Seconds of untimed calls before a timed set on a GPU: an H100 left idle (by CPU work, or a
# benchmark's checks) clocks down, and the next set then timed 2-4x slow.
SPIN_UP_S = 0.25
# back_to_back_ms: calls whose issue the CPU times first, the busy work's margin over that
# issue time, and its ceiling (a queue far longer than this once reset an H100's context).
ISSUE_PROBE_CALLS = 5
ISSUE_MARGIN = 1.5
BUSY_MS_MAX = 400.0


def gpu_clock(ctx) -> bool:
    """Whether `ctx` times passes with GPU timer queries (else glFinish and a wall clock)."""
    return ctx.info()["timer"] == "gl_time_elapsed"


def spin_up(ctx, call) -> None:
    """Calls `call()` untimed: once (compiled, pooled, JIT-compiled on llvmpipe), and on a GPU
    clock for SPIN_UP_S of the GPU's time, so that its clocks are up when timing starts. Each
    call is waited for: issued for SPIN_UP_S unwaited, the calls of reconstruct_urho3d at
    1080p on the H100 queued 1100 to 1900 calls' work (8.9 s on vehicle), and the driver
    reset the context in that queue on its two slowest scenes (docs/spec.md §6.3)."""
    start, spin = time.perf_counter(), gpu_clock(ctx)
    call()
    while spin and time.perf_counter() - start < SPIN_UP_S:
        ctx.finish()
        call()


def median_passes(ctx, frame, method: str, runs: int, **params) -> tuple[dict, object]:
    """Median ms of each pass of `method` over `runs` timed runs after spin_up's untimed
    ones, and the median of their sums under the key "total"; and the clock."""
    spin_up(ctx, lambda: blur(ctx, frame, method, **params))
    times: dict[str, list] = {}
    totals = []
    for _ in range(runs):
        result = blur(ctx, frame, method, **params)
        for key, timing in result.timings.items():
            times.setdefault(key, []).append(timing.ms)
        totals.append(result.total_ms)
        clock = result.clock
        del result  # back to the pool: fresh textures cost GPU time on first use
    medians = {key: statistics.median(ms) for key, ms in times.items()}
    return medians | {"total": statistics.median(totals)}, clock


def back_to_back_ms(ctx, call, calls: int = 50, busy_ms: float = 20.0) -> float:
    """GPU ms per `call()` over `calls` calls issued in a row while the GPU is still busy with
    earlier work, so that it never waits for the CPU between them: one GL timer query around
    the calls. Per-pass timers each hold a pass's ramp-up and drain; a timer around a lone call
    also holds the gaps where the GPU waited for Python. The busy work is sized to last at
    least `busy_ms` and longer than the CPU takes to issue the calls (measured first). It can
    run ahead of them by no more than the context's passes in flight (32, docs/spec.md §6.3),
    though: where a call's passes take Python longer to issue than the GPU to run (a run that
    is not replayed as a plan), the GPU still waits and the figure is Python's issue rate
    (docs/engines.md). On a wall clock (llvmpipe) there is nothing to overlap: the calls are
    timed as they run."""
    spin_up(ctx, call)  # compiled, pooled, planned and the clocks up before the clock
    if gpu_clock(ctx):
        ctx.finish()
        start = time.perf_counter()
        for _ in range(ISSUE_PROBE_CALLS):
            call()
        issue_ms = (time.perf_counter() - start) * 1e3 / ISSUE_PROBE_CALLS
        ctx.finish()
        busy_ms = min(BUSY_MS_MAX, max(busy_ms, ISSUE_MARGIN * calls * issue_ms))
        busy = ctx.shader_pass("passes/accumulate.comp")
        color, total = ctx.pooled((2048, 2048, 4)), ctx.pooled((2048, 2048, 4))

        def run_busy():
            busy.run({"color": color}, {"sum": total}, {"weight": 0.5})

        with ctx.timer() as one:
            run_busy()
        for _ in range(max(1, int(busy_ms / max(one.ms, 1e-3)))):
            run_busy()  # the GPU works through these while the CPU issues the calls below
    with ctx.timer() as timing:
        for _ in range(calls):
            call()
    if gpu_clock(ctx):
        ctx.recycle(color, total)
    return timing.ms / calls


def untimed_calls_ms(ctx, frame, method: str, backend: str | None = None, **params) -> float:
    """GPU ms per untimed call of `method` on `frame`, calls issued back to back
    (back_to_back_ms): no per-pass timers, no GPU waiting for Python."""
    return back_to_back_ms(
        ctx, lambda: blur(ctx, frame, method, backend=backend, timed=False, **params)
    )


def wall_ms(call, runs: int) -> list[float]:
    """Wall-clock ms of each of `runs` calls of `call()`."""
    samples = []
    for _ in range(runs):
        start = time.perf_counter()
        call()
        samples.append((time.perf_counter() - start) * 1e3)
    return samples


def per_call_us(ctx, call, calls: int, clock=time.perf_counter) -> float:
    """µs per `call(i)` over `calls` calls in a loop finished once, by `clock`."""
    ctx.finish()
    start = clock()
    for i in range(calls):
        call(i)
    ctx.finish()
    return 1e6 * (clock() - start) / calls


def post_process_methods() -> list[str]:
    """The sweepable methods that blur a rendered frame (not those rendering sub-frames)."""
    return [n for n in sweep_methods() if method(n).kind != "render"]


def tile_filters() -> list[str]:
    """The tile-based reconstruction filters (kind "filter", docs/spec.md §3), in registry order."""
    return [name for name in methods() if method(name).kind == "filter"]


def optioned_filters() -> list[str]:
    """The tile filters that take the filter options and packed inputs (docs/spec.md §19)."""
    return [name for name in tile_filters() if "packed_inputs" in method(name).params]


def film_method() -> str:
    """The method with a film filter (docs/spec.md §17.6): the engines' parts combined."""
    return next(name for name in methods() if "film_filter" in method(name).params)


def gallery_methods(kind: str) -> list[str]:
    """The methods of `kind` that the failure suite's gallery shows (registered gallery=True),
    in registry order: the small presets' typical methods of that kind."""
    return [name for name in methods() if method(name).kind == kind and method(name).gallery]


def split(text: str) -> list[str]:
    """A comma-separated parameter's items ("" -> [])."""
    return [item for item in text.split(",") if item]


def method_config(text: str) -> tuple[str, dict]:
    """One `config` item, METHOD:KEY=VALUE,KEY=VALUE (numbers, true or false, or one of the
    choices of a choice parameter of METHOD), as (method, parameters)."""
    method, _, given = text.partition(":")
    params = {}
    for item in filter(None, given.split(",")):
        key, equals, value = item.partition("=")
        try:
            if value in ("true", "false"):
                params[key] = value == "true"
            elif value in _choices(method, key):
                params[key] = value
            else:
                params[key] = float(value) if "." in value or "e" in value else int(value)
        except ValueError:
            equals = ""
        if not method or not key or not equals:
            raise ValueError(
                f"blurlab: config {item!r} in {text!r}: give METHOD:KEY=VALUE,... with "
                "numbers, true or false, or a choice of the method's parameter"
            )
    return method, params


def _choices(method_name: str, key: str) -> tuple:
    """The choices of `method_name`'s parameter `key` where it is a choice, else ()."""
    params = method(method_name).params if method_name in methods() else {}
    kind = params[key].kind if key in params else None
    return kind if isinstance(kind, tuple) else ()


def method_runs(names: list[str], film_filter: float = 0.0, configs: str = "") -> list[tuple]:
    """(label, method, parameters) for each method at its defaults; with film_filter > 0,
    film_method() once more with its Gaussian film filter of that σ (docs/spec.md §17.6);
    then a row for each of `configs` (METHOD:KEY=VALUE,...; items separated by ';'), labelled
    with its parameters."""
    runs = [(name, name, {}) for name in names]
    if film_filter > 0:
        label = f"{film_method()}, film_filter={film_filter:g}"
        runs.append((label, film_method(), {"film_filter": film_filter}))
    for item in filter(None, configs.split(";")):
        method, params = method_config(item)
        label = ", ".join([method] + [f"{key}={value}" for key, value in params.items()])
        runs.append((label, method, params))
    return runs
