"""`bl.recommend`: which method, with which parameters, for this scene at this size and budget.

A small sweep answers it: every sweepable method on its default grid, plus the "auto" point of
each parameter that has a rule (k and samples of the tile filters), with PSNR and SSIM reduced
on the GPU. The sweep is cached per scene (name and content), device and size, so asking again
with another budget or target costs nothing. The answer is the cheapest configuration that
reaches `target_psnr`, or the most accurate one within `budget_ms`, or, with both, the cheapest
that reaches the target within the budget; the rows behind it come with it.

`recommend_set` answers the same question for a set of scenes: one configuration for all of
them, the best by an aggregate over the scenes that the user picks (the median, mean, worst,
best or a percentile of a metric; docs/spec.md §23.2), with the per-scene table behind it.
docs/recommend.md.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .. import scenes
from ..context import Context
from ..methods import method
from ..metrics import get, registered
from ..scene import Scene
from ..sizes import DEFAULT_SIZE
from .evaluation import Settings
from .identity import device_identity, row_identity
from .sweep import default_grids, scene_identity, sweep

# What every recommendation's sweep measures: PSNR (target_psnr reads it) and SSIM, from one
# fused GPU pass (docs/spec.md §6). A `metric` to rank by beside them is measured too.
MEASURED = ("psnr", "ssim")
_CACHE: dict[str, pd.DataFrame] = {}


@dataclass
class Recommendation:
    """The answer: a method and its parameters, the row that measured them, and the table of
    every configuration the answer was chosen from (`chosen` marks the answer)."""

    method: str | None
    params: dict
    row: dict | None
    table: pd.DataFrame = field(repr=False)
    question: str = ""

    def __str__(self) -> str:
        if self.row is None:
            fastest = self.table.sort_values("total_ms").iloc[0]
            return (
                f"nothing meets the request ({self.question}); the fastest is {fastest['method']} "
                f"{fastest['params']} at {fastest['total_ms']:.3g} ms, "
                f"PSNR {fastest['psnr']:.2f} dB"
            )
        return (
            f"{self.method} {json.dumps(self.params, sort_keys=True)}: "
            f"{self.row['total_ms']:.3g} ms, PSNR {self.row['psnr']:.2f} dB, "
            f"SSIM {self.row['ssim']:.4f} ({self.question})"
        )


def recommendation_grids() -> dict:
    """The default grids, each extended by the point where every parameter that has an "auto"
    rule is "auto"."""
    grids = {}
    for name, grid in default_grids().items():
        automatic = [k for k, p in method(name).params.items() if p.auto is not None]
        parts = [grid] if isinstance(grid, dict) else list(grid)
        grids[name] = parts + [{k: ["auto"] for k in automatic}] if automatic else grid
    return grids


def recommend(
    ctx: Context,
    scene: Scene | str | os.PathLike,
    size=DEFAULT_SIZE,
    budget_ms: float | None = None,
    target_psnr: float | None = None,
    metric: str = "psnr",
    progress: bool = False,
) -> Recommendation:
    """The cheapest method and parameters that reach `target_psnr` (dB), or the most accurate
    by `metric` (one of ranking_metrics(); which way is better, the registry says) within
    `budget_ms` (the method's GPU time per frame, by the
    context's clock); with both, the cheapest that reaches the target within the budget.
    Returns a Recommendation whose `table` holds the rows it was chosen from; `method` is None
    where no row qualifies (its str() then names the fastest row)."""
    _check_request("blurlab.recommend", budget_ms, ("target_psnr", target_psnr), positive=True)
    if metric not in ranking_metrics():
        raise ValueError(
            f"blurlab.recommend: metric must be one of {ranking_metrics()}, not {metric!r}"
        )
    scene = scenes.get(scene) if isinstance(scene, (str, os.PathLike)) else scene
    table = measured(ctx, scene, size, progress, tuple(dict.fromkeys(MEASURED + (metric,))))
    rows = table
    if budget_ms is not None:
        rows = rows[rows["total_ms"] <= budget_ms]
    if target_psnr is not None:
        rows = rows[rows["psnr"] >= target_psnr]
    if target_psnr is not None:
        question = f"the cheapest with PSNR >= {target_psnr:g} dB"
        if budget_ms is not None:
            question += f" within {budget_ms:g} ms"
    else:
        question = f"the best {metric.upper()} within {budget_ms:g} ms"
    question += f"; {len(table)} configurations on {scene.name} {size[0]}x{size[1]}"
    table = table.assign(chosen=False)
    if rows.empty:
        return Recommendation(None, {}, None, table, question)
    rows = rows.assign(goodness=get(metric).goodness(rows[metric]))
    if target_psnr is not None:
        best = rows.sort_values(["total_ms", "goodness"], ascending=[True, False]).index[0]
    else:
        best = rows.sort_values(["goodness", "total_ms"], ascending=[False, True]).index[0]
    table.loc[best, "chosen"] = True
    row = table.loc[best].to_dict()
    params = json.loads(row["params"])
    for key in params:
        chosen = row.get(f"auto_{key}")
        if params[key] == "auto" and isinstance(chosen, str):
            params[key] = json.loads(chosen)
    return Recommendation(row["method"], params, row, table, question)


def _check_request(caller: str, budget_ms, target: tuple, positive: bool) -> None:
    """A budget (a number > 0) or a target (`target`: its name and value; a number, > 0 where
    `positive`) or both, else an error from `caller` saying what is allowed."""
    name, value = target
    if budget_ms is None and value is None:
        raise ValueError(f"{caller}: give budget_ms, {name} or both")
    for key, given, must_be_positive in (("budget_ms", budget_ms, True), (name, value, positive)):
        if given is None:
            continue
        number = not isinstance(given, bool) and isinstance(given, (int, float))
        if not number or not math.isfinite(given) or (must_be_positive and not given > 0):
            allowed = "a number > 0" if must_be_positive else "a finite number"
            raise ValueError(f"{caller}: {key} must be {allowed}, not {given!r}")


def ranking_metrics() -> list[str]:
    """The registered metrics an answer can rank by: those of single frames with a direction."""
    return [n for n in registered() if get(n).higher_is_better is not None and not get(n).sequence]


def measured(
    ctx: Context, scene: Scene, size, progress: bool = False, metrics=MEASURED
) -> pd.DataFrame:
    """The sweep behind recommend() for this scene, device and size, measuring `metrics`, run
    once and cached by the identity a sweep's rows have (blurlab.studies.identity: the
    scene's name and content, size, shutter, reference, metrics, device, blurlab's version),
    so an edited scene file is measured anew."""
    settings = Settings((int(size[0]), int(size[1])), None, None, tuple(metrics), repeats=3)
    key = row_identity(scene_identity(scene, settings, device_identity(ctx)))
    if key not in _CACHE:
        table = sweep(
            ctx,
            [scene],
            recommendation_grids(),
            size,
            metrics=metrics,
            progress=progress,
            repeats=3,
        )
        _CACHE[key] = table[[math.isfinite(v) for v in table["total_ms"]]].reset_index(drop=True)
    return _CACHE[key]


# An aggregate over a set of scenes: "NAME" or "NAME:METRIC" (docs/spec.md §23.2).
AGGREGATES = ("median", "mean", "worst", "best", "pNN")
_PERCENTILE = re.compile(r"p(\d{1,2}(?:\.\d+)?)")


@dataclass(frozen=True)
class Aggregate:
    """How a configuration's values over a set of scenes become one number: `kind` (one of
    AGGREGATES, a percentile as "p"), `q` (the percentile, 0 < q < 100) and the metric."""

    kind: str
    q: float | None
    metric: str

    def __str__(self) -> str:
        name = f"p{self.q:g}" if self.kind == "p" else self.kind
        return f"{name}:{self.metric}"

    def of(self, values) -> float:
        """The aggregate of `values` (the metric on each scene), in the metric's unit. It is
        taken on the metric's goodness (higher always better), so "worst" and "p10" are the
        bad end whichever way the metric points: p10:flip is the 90th percentile of FLIP."""
        sign = 1.0 if get(self.metric).higher_is_better else -1.0
        good = sign * np.asarray(values, np.float64)
        reduce = {
            "median": np.median,
            "mean": np.mean,
            "worst": np.min,
            "best": np.max,
            "p": lambda g: np.percentile(g, self.q),
        }[self.kind]
        return float(sign * reduce(good))


def parse_aggregate(text: str) -> Aggregate:
    """ "median", "mean", "worst", "best" or "pNN" (the NN-th percentile from the bad end, 0 <
    NN < 100), optionally followed by ":METRIC" (one of ranking_metrics(); default psnr)."""
    if not isinstance(text, str):
        raise TypeError(f"blurlab.recommend: an aggregate is text such as 'p10:psnr', not {text!r}")
    name, _, metric = text.partition(":")
    metric = metric or "psnr"
    allowed = f"one of {', '.join(AGGREGATES)} (pNN: a percentile, 0 < NN < 100)"
    if metric not in ranking_metrics():
        raise ValueError(
            f"blurlab.recommend: aggregate {text!r}: the metric must be one of "
            f"{ranking_metrics()}, not {metric!r}"
        )
    percentile = _PERCENTILE.fullmatch(name)
    if percentile:
        q = float(percentile.group(1))
        if not 0 < q < 100:
            raise ValueError(f"blurlab.recommend: aggregate {text!r}: {allowed}")
        return Aggregate("p", q, metric)
    if name not in AGGREGATES:
        raise ValueError(f"blurlab.recommend: aggregate {text!r}: {allowed}, then ':METRIC'")
    return Aggregate(name, None, metric)


@dataclass
class SetRecommendation:
    """The answer for a set of scenes: a method and its parameters, its aggregate and time
    over the set, `per_scene` (its row on each scene), and `table`, every configuration
    measured on every scene with its aggregate and time (`chosen` marks the answer)."""

    method: str | None
    params: dict
    aggregate: Aggregate
    value: float | None
    time_ms: float | None
    per_scene: pd.DataFrame = field(repr=False)
    table: pd.DataFrame = field(repr=False)
    question: str = ""

    def __str__(self) -> str:
        metric = get(self.aggregate.metric)
        unit = f" {metric.unit}" if metric.unit else ""
        if self.method is None:
            return f"nothing meets the request ({self.question})"
        return (
            f"{self.method} {json.dumps(self.params, sort_keys=True)}: {self.aggregate} "
            f"{self.value:.4g}{unit}, slowest scene {self.time_ms:.3g} ms ({self.question})"
        )


def recommend_set(
    ctx: Context,
    scene_set: Sequence,
    size=DEFAULT_SIZE,
    budget_ms: float | None = None,
    target: float | None = None,
    aggregate: str = "median:psnr",
    progress: bool = False,
) -> SetRecommendation:
    """One configuration for every scene of `scene_set` (built-in names, files, Scenes, or
    "random:A-B" for the random scenes of seeds A to B):
    the best by `aggregate` (parse_aggregate) among those whose slowest scene fits in
    `budget_ms`, or the cheapest whose aggregate reaches `target` (in the metric's unit), or,
    with both, the cheapest that reaches the target within the budget (docs/spec.md §23.2).
    Each scene is measured as recommend() measures it, and cached alike."""
    chosen_aggregate = parse_aggregate(aggregate)
    _check_request("blurlab.recommend_set", budget_ms, ("target", target), positive=False)
    items = [scenes.get(s) if isinstance(s, (str, os.PathLike)) else s for s in expand(scene_set)]
    if not items:
        raise ValueError("blurlab.recommend_set: no scenes")
    wanted = tuple(dict.fromkeys(MEASURED + (chosen_aggregate.metric,)))
    rows = pd.concat(
        [measured(ctx, scene, size, progress, wanted) for scene in items], ignore_index=True
    )
    table = set_table(rows, chosen_aggregate, len(items))
    candidates = table
    if budget_ms is not None:
        candidates = candidates[candidates["time_ms"] <= budget_ms]
    metric = get(chosen_aggregate.metric)
    if target is not None:
        candidates = candidates[metric.goodness(candidates["value"]) >= metric.goodness(target)]
    question = _set_question(chosen_aggregate, budget_ms, target, len(table), items, size)
    table = table.assign(chosen=False)
    if candidates.empty:
        return SetRecommendation(
            None, {}, chosen_aggregate, None, None, rows.iloc[:0], table, question
        )
    ranked = candidates.assign(goodness=metric.goodness(candidates["value"]))
    if target is not None:
        order = ranked.sort_values(["time_ms", "goodness"], ascending=[True, False])
    else:
        order = ranked.sort_values(["goodness", "time_ms"], ascending=[False, True])
    best = order.index[0]
    table.loc[best, "chosen"] = True
    answer = table.loc[best]
    per_scene = rows[(rows["method"] == answer["method"]) & (rows["params"] == answer["params"])]
    return SetRecommendation(
        answer["method"],
        json.loads(answer["params"]),
        chosen_aggregate,
        float(answer["value"]),
        float(answer["time_ms"]),
        per_scene.reset_index(drop=True),
        table,
        question,
    )


_SEED_RANGE = re.compile(r"random:(\d+)-(\d+)")


def expand(scene_set: Sequence) -> list:
    """`scene_set` with each "random:A-B" replaced by the random scenes "random:A" ...
    "random:B" (docs/spec.md §22); other items as they are."""
    if isinstance(scene_set, (str, os.PathLike)):
        scene_set = [scene_set]
    items = []
    for item in scene_set:
        seeds = _SEED_RANGE.fullmatch(item) if isinstance(item, str) else None
        if seeds is None:
            items.append(item)
            continue
        first, last = int(seeds.group(1)), int(seeds.group(2))
        if last < first:
            raise ValueError(f"blurlab.recommend: {item!r}: a seed range A-B needs A <= B")
        items += [f"random:{seed}" for seed in range(first, last + 1)]
    return items


def set_table(rows: pd.DataFrame, aggregate: Aggregate, scene_count: int) -> pd.DataFrame:
    """Per configuration (method, params) measured on all `scene_count` scenes: its
    aggregate `value`, `time_ms` (its slowest scene: a frame's budget holds on every scene)
    and the median time over the scenes."""
    out = []
    for (name, params), group in rows.groupby(["method", "params"], sort=False):
        values = group[aggregate.metric]
        if group["scene"].nunique() < scene_count or not np.isfinite(values).all():
            continue  # not measured on every scene: it cannot answer for the set
        out.append(
            {
                "method": name,
                "params": params,
                "scenes": scene_count,
                "value": aggregate.of(values),
                "time_ms": float(group["total_ms"].max()),
                "median_ms": float(group["total_ms"].median()),
            }
        )
    return pd.DataFrame(out)


def _set_question(aggregate, budget_ms, target, configurations, items, size) -> str:
    if target is not None:
        question = f"the cheapest with {aggregate} >= {target:g}"
        if budget_ms is not None:
            question += f" within {budget_ms:g} ms"
    else:
        question = f"the best {aggregate} within {budget_ms:g} ms"
    return f"{question}; {configurations} configurations on {len(items)} scenes {size[0]}x{size[1]}"
