"""Methods over time (docs/spec.md §21): the orders of each method and TAA on the built-in and
failure scenes, and each method's error and temporal instability as the frame rate changes at
a fixed shutter angle. docs/temporal.md shows the numbers of the temporal_orders and
frame_rate benchmarks."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .. import metrics
from ..methods import method as method_info
from ..methods import methods as method_names
from ..scene import scenes
from ..temporal.sequences import ORDERS, SequenceRun, sequence
from .evaluation import PhaseClock

# What a run is called when no method blurs: the frames as rendered, or TAA alone.
NO_METHOD = "(none)"


def sequence_methods() -> list[str]:
    """Every method that runs frame by frame (the registry's all but `sequence` kind)."""
    return [n for n in method_names() if method_info(n).sweepable]


def orders_of(name: str | None) -> tuple[str, ...]:
    """The orders (docs/spec.md §21.4) that apply to method `name` (None: no method)."""
    if name is None:
        return ("none", "blur_then_taa")
    if method_info(name).renders:
        return ("none", "blur_then_taa")
    return ORDERS


def measured(run: SequenceRun, warmup: int) -> dict:
    """psnr (of the mean squared error over the frames after `warmup`) and temporal
    instability over the same frames, from the run's per-frame reductions on the GPU."""
    mse = float(np.mean(run.frame_mse[warmup:]))
    return {
        "psnr": metrics.psnr_from_mse(mse),
        "mse": mse,
        "temporal_instability": run.instability_after(warmup),
    }


def evaluate_orders(
    ctx,
    scene_names,
    methods,
    size,
    frames: int,
    warmup: int,
    reference_samples: int,
    fps: float = 60.0,
    shutter_angle: float = 180.0,
    taa: dict | None = None,
    on_run=None,
    orders: tuple[str, ...] = ORDERS,
    clock=None,
) -> pd.DataFrame:
    """One row per (scene, method, order): psnr, mse and temporal instability of the frames
    after `warmup` against the sequence reference. Method NO_METHOD is the frames as rendered
    (order "none") and TAA alone ("blur_then_taa"). Only the `orders` that apply to a method
    run. `on_run(scene, method, order, run)`, if given, sees each method's SequenceRun before
    it is dropped. `clock` (blurlab.studies.evaluation.PhaseClock), if given, counts the
    sequences' rendering as "sequences" and the runs as "runs"."""
    clock = clock or PhaseClock()
    rows = []
    for name in scene_names:
        with clock("sequences"):
            seq = sequence(
                ctx,
                scenes.get(name),
                size,
                fps,
                warmup + frames,
                shutter_angle,
                reference_samples=reference_samples,
            )
            ctx.finish()  # the references' GPU work counted here, not in the first run
        for method in [None, *methods]:
            for order in [o for o in orders_of(method) if o in orders]:
                with clock("runs"):
                    run = seq.run(method, order, taa=taa, metrics=("psnr",))
                if on_run is not None and method is not None:
                    on_run(name, method, order, run)
                rows.append(
                    {
                        "scene": name,
                        "fps": fps,
                        "method": NO_METHOD if method is None else method,
                        "order": order,
                        **measured(run, warmup),
                    }
                )
    return pd.DataFrame(rows)


# Orders within this many dB (or instability units) of the best tie: each counts as a winner.
TIE = {"psnr": 0.01, "temporal_instability": 1e-5}


def winners(rows: pd.DataFrame, measure: str) -> pd.Series:
    """For rows of one (scene, method), which orders are best by `measure` (ties included)."""
    values = rows[measure]
    best = values.max() if measure == "psnr" else values.min()
    return rows["order"][(values - best).abs() <= TIE[measure]]


def orders_summary(table: pd.DataFrame) -> dict:
    """From evaluate_orders' table: the median psnr and instability per (method, order) over
    the scenes; per method, the order with the best median psnr, its margin over the second,
    the steadiest order, and the scenes where another order is best by psnr (where the winner
    flips; ties within TIE are no flip); and on how many (scene, method) pairs each order is
    best, or tied for best, by each measure."""
    methods_only = table[table["method"] != NO_METHOD]
    medians = methods_only.groupby(["method", "order"])[["psnr", "temporal_instability"]].median()
    pairs = methods_only.groupby(["scene", "method"], sort=False)
    rows = []
    for method, group in medians.groupby(level="method"):
        ranked = group["psnr"].droplevel("method").sort_values(ascending=False)
        flips = []
        for (scene, name), pair in pairs:
            best = list(winners(pair, "psnr"))
            if name == method and ranked.index[0] not in best:
                flips.append(f"{scene} ({', '.join(best)})")
        rows.append(
            {
                "method": method,
                "best": ranked.index[0],
                "margin_db": ranked.iloc[0] - ranked.iloc[1] if len(ranked) > 1 else np.nan,
                "steadiest": group["temporal_instability"].droplevel("method").idxmin(),
                "flips": "; ".join(flips),
            }
        )
    wins = {
        measure: pd.concat([winners(pair, measure) for _, pair in pairs])
        .value_counts()
        .reindex(ORDERS, fill_value=0)
        for measure in TIE
    }
    return {"medians": medians, "winners": pd.DataFrame(rows), "wins": wins}


def evaluate_frame_rates(
    ctx,
    scene_names,
    methods,
    size,
    rates,
    frames: int,
    warmup: int,
    reference_samples: int,
    shutter_angle: float = 180.0,
) -> pd.DataFrame:
    """evaluate_orders at each frame rate of `rates`, the method alone and before TAA, with
    `relative_mse`: the method's mse over the mse of the frames as rendered at the same frame
    rate (how much of the shutter's blur it misses; flat across rates when the method's error
    follows the shutter alone)."""
    tables = []
    for fps in rates:
        table = evaluate_orders(
            ctx,
            scene_names,
            methods,
            size,
            frames,
            warmup,
            reference_samples,
            fps,
            shutter_angle,
            orders=("none", "blur_then_taa"),
        )
        sharp = table[(table["method"] == NO_METHOD) & (table["order"] == "none")]
        baseline = sharp.set_index("scene")["mse"]
        table["relative_mse"] = table["mse"] / table["scene"].map(baseline).clip(lower=1e-12)
        tables.append(table)
    return pd.concat(tables, ignore_index=True)


def frame_rate_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per (method, order) and frame rate: median psnr, instability and relative mse over the
    scenes, and `relative_mse_spread`: the largest over the smallest median relative mse across
    the frame rates (1: the error follows the shutter alone)."""
    medians = (
        table.groupby(["method", "order", "fps"])[["psnr", "temporal_instability", "relative_mse"]]
        .median()
        .reset_index()
    )
    spread = medians.groupby(["method", "order"])["relative_mse"].agg(
        lambda v: v.max() / max(v.min(), 1e-12)
    )
    medians["relative_mse_spread"] = [
        spread[(m, o)] for m, o in zip(medians["method"], medians["order"], strict=True)
    ]
    return medians
