"""Do blurlab's metrics rank methods as a model of human vision does? (docs/spec.md §21.3,
docs/temporal.md) Every per-frame method runs on each sequence under TAA (blur_then_taa); on
each sequence the methods are ranked by each metric and by the model of vision (`MODEL`:
ColorVideoVDP or FovVideoVDP, blurlab.metrics.perceptual), and Kendall's τ between the two
rankings says how far they agree: 1 the same order, 0 none, −1 reversed. Over the sequences:
the mean τ with a percentile bootstrap interval over sequences
(studies.rankings.bootstrap_interval), and how often the metric's best method is the model's.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats

from .. import metrics
from ..methods.params import Param, typed
from ..metrics import perceptual
from ..scene import scenes
from ..temporal.sequences import sequence
from . import temporal
from .rankings import bootstrap_interval

METRICS = ("psnr", "flip", "temporal_instability")  # the metrics judged
ORDER = "blur_then_taa"  # every per-frame method runs in this order (docs/spec.md §21.4)
MODEL = Param(
    "colorvideovdp",
    tuple(perceptual.MODELS),
    "the model of vision the metrics' rankings are held against (each keeps a record of its own)",
)


def checked_model(name: str) -> str:
    """`name` as the `model` parameter takes it (MODEL), or an error saying what is allowed."""
    return typed("perceptual_agreement", "model", name, MODEL)


def require(name: str) -> perceptual.Model:
    """Model `name`, or an ImportError saying what to install where it is not installed."""
    name = checked_model(name)
    chosen = perceptual.model(name)
    if not perceptual.available(name):
        raise ImportError(
            f"blurlab: the perceptual agreement with {chosen.label} ({name}) needs "
            f"{perceptual.INSTALL}"
        )
    return chosen


def scores(
    ctx,
    scene_names: Sequence[str],
    size,
    methods: Sequence[str] | None = None,
    frames: int = 8,
    warmup: int = 4,
    reference_samples: int = 64,
    fps: float = 60.0,
    model: str = MODEL.default,
) -> pd.DataFrame:
    """One row per (scene, method) under TAA: psnr (of the mean squared error) and flip (the
    per-frame mean) over the `frames` after `warmup`, temporal_instability over the same frames,
    and the JOD of the same frames at `fps` by `model` (a column of that name)."""
    chosen = require(model)
    methods = list(methods or temporal.sequence_methods())
    rows = []
    for name in scene_names:
        seq = sequence(
            ctx, scenes.get(name), size, fps, warmup + frames, reference_samples=reference_samples
        )
        for method in methods:
            run = seq.run(method, ORDER, metrics=("psnr", "flip"))
            measured = temporal.measured(run, warmup)
            rows.append(
                {
                    "scene": name,
                    "method": method,
                    "psnr": measured["psnr"],
                    "flip": float(np.mean(run.scores["flip"][warmup:])),
                    "temporal_instability": measured["temporal_instability"],
                    chosen.name: perceptual.judge(
                        chosen.name, run.references[warmup:], run.color[warmup:], fps
                    ),
                }
            )
    return pd.DataFrame(rows)


def taus(
    table: pd.DataFrame, judged: Sequence[str] = METRICS, model: str = MODEL.default
) -> pd.DataFrame:
    """Per scene (rows) and judged metric (columns): Kendall's τ-b between the methods' order
    by the metric and by `model`, the table's column of that name (each metric's own
    direction: its `goodness`); NaN where either gives every method the same value."""
    model = checked_model(model)
    out = {}
    for scene, rows in table.groupby("scene", sort=False):
        truth = rows[model]  # JOD: higher is better
        out[scene] = {name: _tau(metrics.get(name).goodness(rows[name]), truth) for name in judged}
    return pd.DataFrame.from_dict(out, orient="index")


def _tau(a, b) -> float:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    if np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    return float(stats.kendalltau(a, b).statistic)


def agreement(
    table: pd.DataFrame, judged: Sequence[str] = METRICS, model: str = MODEL.default
) -> pd.DataFrame:
    """One row per judged metric: the sequences, the mean τ over them with its 95 % bootstrap
    interval against `model` (as `taus`), the median and lowest τ, and the share of sequences
    on which the metric's best method is the model's best (ties on either side count as
    agreement)."""
    per_scene = taus(table, judged, model)
    rows = []
    for name in judged:
        values = per_scene[name].dropna().to_numpy()
        low, high = bootstrap_interval(values, np.mean) if values.size else (np.nan, np.nan)
        rows.append(
            {
                "metric": name,
                "sequences": int(values.size),
                "tau_mean": float(values.mean()) if values.size else np.nan,
                "tau_low": low,
                "tau_high": high,
                "tau_median": float(np.median(values)) if values.size else np.nan,
                "tau_min": float(values.min()) if values.size else np.nan,
                "same_best": _same_best(table, name, model),
            }
        )
    return pd.DataFrame(rows)


def _same_best(table: pd.DataFrame, name: str, model: str) -> float:
    hits = []
    for _, rows in table.groupby("scene", sort=False):
        mine = metrics.get(name).goodness(rows[name])
        truth = rows[model]  # JOD: higher is better
        best_mine = set(rows["method"][mine == mine.max()])
        best_truth = set(rows["method"][truth == truth.max()])
        hits.append(bool(best_mine & best_truth))
    return float(np.mean(hits)) if hits else float("nan")
