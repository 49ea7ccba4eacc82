"""Helpers shared by the benchmark scripts: device description and result records."""

from __future__ import annotations

import argparse
import datetime
import json
import platform
import statistics
import time
from pathlib import Path

import blurlab as bl

# Seconds of untimed calls before a timed set: an H100 left idle (by CPU work, or a benchmark's
# checks) clocks down, and the next set then timed 2-4x slow (engines.py --variants and
# speed_floor.py's metrics, 2026-11-24).
SPIN_UP_S = 0.25


def open_context(device: str):
    """The blurlab Context a benchmark's --device names: auto, gpu, software or an EGL index."""
    import blurlab as bl

    return bl.Context(int(device) if device.isdigit() else device)


def describe(ctx) -> dict:
    """Which device measured: renderer, GL version, timer clock, host."""
    info = ctx.info()
    return {
        "date": datetime.date.today().isoformat(),
        "device": info["device"],
        "renderer": info["renderer"],
        "gl_version": info["version"],
        "timer": info["timer"],
        "host_cpu": platform.processor() or platform.machine(),
    }


def summarize(samples_ms: list[float]) -> dict:
    return {
        "median_ms": statistics.median(samples_ms),
        "min_ms": min(samples_ms),
        "runs": len(samples_ms),
    }


def save(path: str | None, record: dict) -> None:
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(json.dumps(record, indent=2))


def method_runs(
    names: list[str], film_filter: float = 0.0, configs: tuple = ()
) -> list[tuple[str, str, dict]]:
    """(label, method, parameters) for each method at its defaults, and with film_filter > 0
    gather_coverage once more with its Gaussian film filter of that σ (docs/spec.md §17.6),
    labelled with it: the row to compare against an antialiased reference. Then a row for each
    of `configs`, (method, parameters) pairs (method_config), labelled with its parameters."""
    runs = [(name, name, {}) for name in names]
    if film_filter > 0:
        label = f"gather_coverage, film_filter={film_filter:g}"
        runs.append((label, "gather_coverage", {"film_filter": film_filter}))
    for method, params in configs:
        label = ", ".join([method] + [f"{key}={value}" for key, value in params.items()])
        runs.append((label, method, params))
    return runs


def method_config(text: str) -> tuple[str, dict]:
    """--config's argument, METHOD:KEY=VALUE,KEY=VALUE (numbers, true or false), as (method,
    parameters)."""
    method, _, given = text.partition(":")
    params = {}
    for item in filter(None, given.split(",")):
        key, equals, value = item.partition("=")
        try:
            if value in ("true", "false"):
                params[key] = value == "true"
            else:
                params[key] = float(value) if "." in value or "e" in value else int(value)
        except ValueError:
            equals = ""
        if not method or not key or not equals:
            raise argparse.ArgumentTypeError(
                f"{item!r} in {text!r}: give METHOD:KEY=VALUE,... with numbers, true or false"
            )
    return method, params


def add_config_argument(parser) -> None:
    """--config (repeatable), parsed by method_config, for method_runs' `configs`."""
    parser.add_argument(
        "--config",
        type=method_config,
        action="append",
        default=[],
        help="METHOD:KEY=VALUE,...: a row of that method with those parameters (repeatable)",
    )


def spin_up(call, seconds: float = SPIN_UP_S) -> None:
    """Calls `call()` untimed for `seconds`, so the GPU's clocks are up when timing starts."""
    start = time.perf_counter()
    while time.perf_counter() - start < seconds:
        call()


def median_passes(ctx, frame, method: str, runs: int, **params) -> tuple[dict, object]:
    """Median ms of each pass of `method` over `runs` timed runs after common.SPIN_UP_S of
    untimed ones, and the last run's result."""
    spin_up(lambda: bl.blur(ctx, frame, method, **params))
    times: dict[str, list] = {}
    for _ in range(runs):
        result = bl.blur(ctx, frame, method, **params)
        for key, timing in result.timings.items():
            times.setdefault(key, []).append(timing.ms)
    return {key: statistics.median(ms) for key, ms in times.items()}, result


def back_to_back_ms(ctx, call, calls: int = 50, busy_ms: float = 20.0, warm=None) -> float:
    """GPU ms per `call()` over `calls` calls issued in a row while the GPU is still busy with
    earlier work, so that it never waits for the CPU between them: one GL timer query around
    the calls, whose passes carry no timers of their own. Per-pass timers each hold a pass's
    ramp-up and drain; a timer around a lone call also holds the gaps where the GPU waited for
    Python to issue the next pass. On a wall clock (llvmpipe) there is nothing to overlap: the
    calls are timed as they run. `warm`: what to spin the GPU up with, where `call` should not
    run for that long (default: `call`)."""
    spin_up(warm or call)  # compiled, pooled, planned and the clocks up before the clock
    gpu_clock = ctx.info()["timer"] == "gl_time_elapsed"
    if gpu_clock:
        busy = ctx.shader_pass("passes/accumulate.comp")
        color, total = ctx.pooled((2048, 2048, 4)), ctx.pooled((2048, 2048, 4))
        run_busy = lambda: busy.run({"color": color}, {"sum": total}, {"weight": 0.5})  # noqa: E731
        with ctx.timer() as one:
            run_busy()
        for _ in range(max(1, int(busy_ms / max(one.ms, 1e-3)))):
            run_busy()  # the GPU works through these while the CPU issues the calls below
    with ctx.timer() as timing:
        for _ in range(calls):
            call()
    if gpu_clock:
        ctx.recycle(color, total)
    return timing.ms / calls
