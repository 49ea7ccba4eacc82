"""How `blurlab recommend` times the configurations its answer could be (docs/recommend.md):
each again, TIMING_RUNS runs after an untimed one, for the median and an interval, the runs
kept on disk by the sweep row's identity so that the same question in another process measures
nothing."""

from __future__ import annotations

import json
import math
import os
import statistics
from pathlib import Path

import pandas as pd

from ..methods import blur_steps, render_steps

# The configurations an answer could be are timed again, TIMING_RUNS runs each, for an
# interval: with 15 runs, the 4th and 12th fastest bound the median with 96.5 % confidence
# (a distribution-free interval: the binomial(15, 1/2) mass between them).
TIMING_RUNS = 15
INTERVAL_RANKS = (3, 11)  # 0-based ranks of the sorted runs bounding the median


def timed_again(ctx, scene, size, table, indices, path: Path | None) -> pd.DataFrame:
    """`table` with ms_low, ms_high and total_ms from TIMING_RUNS runs of each row of
    `indices` (its median and the interval INTERVAL_RANKS bound); the other rows keep the
    sweep's total_ms and NaN bounds (or the bounds an earlier call gave them). Runs are kept in
    the JSON file `path` by row identity."""
    if "ms_low" not in table:
        table = table.assign(ms_low=math.nan, ms_high=math.nan)
    kept = read_runs(path) if path is not None else {}
    frames_of: dict = {}
    changed = False
    for index in indices:
        row = table.loc[index]
        key = row.get("identity")  # a sweep row's identity (absent from a table made by hand)
        runs = kept.get(key)
        if runs is None:
            runs = time_runs(ctx, scene, size, row, frames_of)
            if isinstance(key, str):
                kept[key] = runs
                changed = True
        ordered = sorted(runs)
        table.loc[index, "total_ms"] = statistics.median(ordered)
        table.loc[index, "ms_low"] = ordered[INTERVAL_RANKS[0]]
        table.loc[index, "ms_high"] = ordered[INTERVAL_RANKS[1]]
    if changed and path is not None:
        write_whole(path, kept)
    return table


def time_runs(ctx, scene, size, row, frames_of: dict) -> list[float]:
    """TIMING_RUNS timed runs of a row's configuration, after one untimed run, on the
    scene's G-buffers (their total pass time each, as the sweep's total_ms sums them)."""
    params = json.loads(row["params"])
    steps = params.pop("steps", 1)
    backend = row.get("backend") if isinstance(row.get("backend"), str) else None
    key = (row["method"], steps, json.dumps(params, sort_keys=True))
    if key not in frames_of:
        frames_of[key] = render_steps(ctx, scene, row["method"], steps, size, **params)
    frames = frames_of[key]
    blur_steps(ctx, frames, row["method"], backend, **params)
    runs = []
    for _ in range(TIMING_RUNS):
        result = blur_steps(ctx, frames, row["method"], backend, **params)
        runs.append(float(sum(t.ms for t in result.timings.values())))
        del result
    return runs


def read_runs(path: Path) -> dict:
    """A timings file's {row identity: [ms, ...]}; an unreadable or malformed one is empty."""
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    if not isinstance(data, dict):
        return {}
    return {
        k: v
        for k, v in data.items()
        if isinstance(v, list)
        and len(v) == TIMING_RUNS
        and all(isinstance(x, float) and math.isfinite(x) for x in v)
    }


def write_whole(path: Path, data: dict) -> None:
    """Writes `data` to `path` whole or not at all (a temporary file, then a rename)."""
    temporary = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    temporary.write_text(json.dumps(data))
    os.replace(temporary, path)
