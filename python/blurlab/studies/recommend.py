"""`bl.recommend`: which method, with which parameters, for this scene at this size and budget.

A small sweep answers it: every sweepable method on its default grid, plus the "auto" point of
each parameter that has a rule (k and samples of the tile filters), with PSNR and SSIM reduced
on the GPU. The sweep is kept on disk (cache_dir()) by the identity its rows have (scene name
and content, device, code, size, ...), so asking again, with another budget or target or in
another process, measures nothing. The configurations the answer could be are timed again for
an interval of their median. The answer is the cheapest configuration that reaches
`target_psnr` (or one as fast within the timing noise and more accurate), or the most accurate
one within `budget_ms`, or, with both, the cheapest that reaches the target within the budget;
the rows behind it come with it, with the near miss where there is one.

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
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .._paths import cache_root
from ..core.context import Context
from ..methods import method
from ..metrics import get, registered
from ..scene import scenes
from ..scene.model import Scene
from ..sizes import DEFAULT_SIZE
from .evaluation import Settings
from .identity import device_identity, row_identity
from .recommend_timing import timed_again
from .sweep import default_grids, scene_identity, sweep

# What every recommendation's sweep measures: PSNR (target_psnr reads it) and SSIM, from one
# fused GPU pass (docs/spec.md §6). A `metric` to rank by beside them is measured too.
MEASURED = ("psnr", "ssim")
SWEEP_REPEATS = 3  # timed runs of each configuration in the sweep (its median is total_ms)
# Contenders: the rows within CONTENDER_SPAN of the fastest that qualify (a target), or of the
# budget (a budget), at most MAX_CONTENDERS of them, the best first.
CONTENDER_SPAN = 1.5
MAX_CONTENDERS = 8
# A near miss: a row that gives at least NEAR_MISS_DB more PSNR for at most NEAR_MISS_TIME
# times the answer's time (or the budget's), named beside the answer.
NEAR_MISS_DB = 1.0
NEAR_MISS_TIME = 1.25
_CACHE: dict[str, pd.DataFrame] = {}


def cache_dir() -> Path:
    """Where answers' sweeps and timings are kept between commands: the `recommend` folder of
    blurlab's cache (BLURLAB_CACHE_DIR, else $XDG_CACHE_HOME/blurlab, else ~/.cache/blurlab)."""
    return cache_root() / "recommend"


@dataclass
class Recommendation:
    """The answer: a method and its parameters, the row that measured them, and the table of
    every configuration the answer was chosen from (`chosen` marks the answer; `ms_low` and
    `ms_high` bound the median time of the contenders timed again). `auto`: the parameters
    whose value the "auto" rule chose. `notes`: what the answer line cannot say (a choice made
    within the timing noise, a fit within the budget only within it). `near_miss`: a row with
    much more accuracy for a little more time, or None. `measured_at`: when the sweep behind
    it was run (UTC; an earlier command's, where it came from the cache)."""

    method: str | None
    params: dict
    row: dict | None
    table: pd.DataFrame = field(repr=False)
    question: str = ""
    auto: tuple = ()
    notes: tuple = ()
    near_miss: dict | None = None
    measured_at: str = ""

    def __str__(self) -> str:
        if self.row is None:
            fastest = self.table.sort_values("total_ms").iloc[0]
            return (
                f"nothing meets the request ({self.question}); the fastest is {fastest['method']} "
                f"{fastest['params']} at {fastest['total_ms']:.3g} ms, "
                f"PSNR {fastest['psnr']:.2f} dB"
            )
        auto = f' ({" and ".join(self.auto)} chosen by "auto")' if self.auto else ""
        return (
            f"{self.method} {json.dumps(self.params, sort_keys=True)}{auto}: "
            f"{_time_text(self.row)}, PSNR {self.row['psnr']:.2f} dB, "
            f"SSIM {self.row['ssim']:.4f} ({self.question})"
        )

    def details(self) -> list[str]:
        """The lines that follow the answer: its notes, the near miss and where it came from."""
        lines = list(self.notes)
        if self.near_miss is not None:
            miss, row = self.near_miss, self.near_miss["row"]
            lines.append(
                f"near miss: {row['method']} {row['params']}: {_time_text(row)}, PSNR "
                f"{row['psnr']:.2f} dB: {miss['gain_db']:+.2f} dB for {miss['extra']}"
            )
        if self.measured_at:
            lines.append(f"measured {self.measured_at}")
        return lines

    def front(self) -> pd.DataFrame:
        """The table's Pareto front: the rows no other row beats in both time and PSNR,
        fastest first."""
        ordered = self.table.sort_values(["total_ms", "psnr"], ascending=[True, False])
        best = -math.inf
        keep = []
        for index, value in ordered["psnr"].items():
            if value > best:
                keep.append(index)
                best = value
        return ordered.loc[keep]


def _time_text(row) -> str:
    """A row's median time, with its interval where it was timed again."""
    low, high = row.get("ms_low"), row.get("ms_high")
    if low is None or not (isinstance(low, float) and math.isfinite(low)):
        return f"{row['total_ms']:.3g} ms"
    return f"{row['total_ms']:.3g} ms [{low:.3g}, {high:.3g}]"


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
    cache: bool = True,
) -> Recommendation:
    """The cheapest method and parameters that reach `target_psnr` (dB), or the most accurate
    by `metric` (one of ranking_metrics(); which way is better, the registry says) within
    `budget_ms` (the method's GPU time per frame, by the context's clock); with both, the
    cheapest that reaches the target within the budget.

    The rows an answer could be are timed again (TIMING_RUNS runs each) for an interval of
    their median time. With a target, rows whose intervals overlap the cheapest's are equally
    cheap within the timing noise, and the most accurate of them is the answer (its notes say
    so). A row with NEAR_MISS_DB more PSNR for at most NEAR_MISS_TIME times the time is
    named as a near miss. `cache`: keep the sweep and the timings on disk (cache_dir()),
    keyed as sweep rows are, so the same question in another process measures nothing.
    Returns a Recommendation whose `table` holds the rows it was chosen from; `method` is None
    where no row qualifies (its str() then names the fastest row)."""
    _check_request("blurlab.recommend", budget_ms, ("target_psnr", target_psnr), positive=True)
    if metric not in ranking_metrics():
        raise ValueError(
            f"blurlab.recommend: metric must be one of {ranking_metrics()}, not {metric!r}"
        )
    scene = scenes.get(scene) if isinstance(scene, (str, os.PathLike)) else scene
    wanted = tuple(dict.fromkeys(MEASURED + (metric,)))
    table = measured(ctx, scene, size, progress, wanted, cache=cache)
    measured_at, sweep_file = table.attrs["measured_at"], table.attrs["cache_file"]
    floor = f"PSNR >= {target_psnr:g} dB" if target_psnr is not None else None
    question = _question(metric.upper(), floor, budget_ms)
    question += f"; {len(table)} configurations on {scene.name} {size[0]}x{size[1]}"
    table = table.assign(goodness=get(metric).goodness(table[metric]))
    timings = Path(sweep_file).with_suffix(".timings.json") if sweep_file else None
    # A contender's median of 15 runs can come out slower than a row the sweep timed 3 times
    # and that was not a contender, which then looks the fastest on a noisier time: the
    # contenders are chosen again from the new times until each has been timed again (each
    # row at most once, so this ends).
    timed: set = set()
    while contenders := [i for i in _contenders(table, budget_ms, target_psnr) if i not in timed]:
        table = timed_again(ctx, scene, size, table, contenders, timings)
        timed.update(contenders)
    table = table.assign(chosen=False)
    best, notes = choose(table, budget_ms, target_psnr, metric)
    if best is None:
        return Recommendation(None, {}, None, table.drop(columns="goodness"), question)
    table.loc[best, "chosen"] = True
    row = table.loc[best].to_dict()
    params = json.loads(row["params"])
    auto = []
    for key in params:
        value = _auto_value(row.get(f"auto_{key}"))
        if params[key] == "auto" and value is not None:
            params[key] = value
            auto.append(key)
    near = near_miss(table, row, budget_ms)
    return Recommendation(
        row["method"], params, row, table.drop(columns="goodness"), question, tuple(auto),
        tuple(notes), near, measured_at,
    )  # fmt: skip


def choose(table: pd.DataFrame, budget_ms, target_psnr, metric: str = "psnr"):
    """(the index of the answer in `table`, its notes), or (None, []) where no row qualifies.
    `table`: total_ms (median), ms_low and ms_high (its interval, NaN where not timed again),
    psnr, `metric` and goodness (the metric, higher better). With a target, the rows that
    qualify and whose interval overlaps the fastest one's are as fast within the timing
    noise, and the most accurate of them is the answer; with a budget alone, the most
    accurate row whose median fits."""
    rows = table
    if budget_ms is not None:
        rows = rows[rows["total_ms"] <= budget_ms]
    if target_psnr is not None:
        rows = rows[rows["psnr"] >= target_psnr]
    if rows.empty:
        return None, []
    notes = []
    if target_psnr is not None:
        fastest = rows.sort_values(["total_ms", "goodness"], ascending=[True, False]).iloc[0]
        ties = rows[rows["ms_low"] <= fastest["ms_high"]] if _timed(fastest) else rows.iloc[:0]
        best = rows.loc[[fastest.name]] if ties.empty else ties
        best = best.sort_values(["goodness", "total_ms"], ascending=[False, True]).index[0]
        if best != fastest.name:
            notes.append(
                f"as fast as the fastest that qualifies ({fastest['method']} "
                f"{fastest['params']}, {_time_text(fastest)}) within the timing noise, and "
                f"more accurate ({table.loc[best, metric]:.4g} against {fastest[metric]:.4g} "
                f"{metric.upper()}), so chosen"
            )
    else:
        best = rows.sort_values(["goodness", "total_ms"], ascending=[False, True]).index[0]
    chosen = table.loc[best]
    if budget_ms is not None and _timed(chosen) and chosen["ms_high"] > budget_ms:
        notes.append(
            f"fits the {budget_ms:g} ms budget by its median time; its interval "
            f"[{chosen['ms_low']:.3g}, {chosen['ms_high']:.3g}] ms reaches beyond it"
        )
    return best, notes


def _auto_value(value):
    """What an "auto" parameter chose, as the sweep's auto_KEY column holds it: JSON text in a
    fresh table (a list where steps chose several), a number once read back from the CSV
    file; None where the row has none."""
    if isinstance(value, str):
        return json.loads(value)
    if isinstance(value, (int, float)) and math.isfinite(value):
        return int(value) if float(value).is_integer() else float(value)
    return None


def _timed(row) -> bool:
    return isinstance(row["ms_low"], float) and math.isfinite(row["ms_low"])


def _contenders(table: pd.DataFrame, budget_ms, target_psnr) -> list:
    """The rows whose time decides the answer, best first: those that reach the target
    within CONTENDER_SPAN of the fastest that does (a target), or the most accurate within
    CONTENDER_SPAN of the budget (a budget alone); at most MAX_CONTENDERS."""
    rows = table
    if target_psnr is not None:
        rows = rows[rows["psnr"] >= target_psnr]
        if budget_ms is not None:
            rows = rows[rows["total_ms"] <= budget_ms * CONTENDER_SPAN]
        if rows.empty:
            return []
        rows = rows[rows["total_ms"] <= rows["total_ms"].min() * CONTENDER_SPAN]
        rows = rows.sort_values("total_ms")
    else:
        rows = rows[rows["total_ms"] <= budget_ms * CONTENDER_SPAN]
        rows = rows.sort_values(["goodness", "total_ms"], ascending=[False, True])
    return list(rows.index[:MAX_CONTENDERS])


def near_miss(table: pd.DataFrame, row: dict, budget_ms) -> dict | None:
    """The row with the most PSNR among those that give NEAR_MISS_DB more than the answer for
    at most NEAR_MISS_TIME times its time (a budget alone: times the budget), or None."""
    limit = (budget_ms if budget_ms is not None else row["total_ms"]) * NEAR_MISS_TIME
    better = table[
        (table["psnr"] >= row["psnr"] + NEAR_MISS_DB)
        & (table["total_ms"] <= limit)
        & (table["total_ms"] > (budget_ms if budget_ms is not None else row["total_ms"]))
    ]
    if better.empty:
        return None
    miss = better.sort_values(["psnr", "total_ms"], ascending=[False, True]).iloc[0].to_dict()
    extra_ms = miss["total_ms"] - row["total_ms"]
    extra = f"{extra_ms:.3g} ms more ({extra_ms / row['total_ms']:+.0%} time)"
    if budget_ms is not None:
        extra += f", {miss['total_ms'] / budget_ms - 1:.0%} over the budget"
    return {"row": miss, "gain_db": miss["psnr"] - row["psnr"], "extra": extra}


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
    ctx: Context, scene: Scene, size, progress: bool = False, metrics=MEASURED, cache: bool = True
) -> pd.DataFrame:
    """The sweep behind recommend() for this scene, device and size, measuring `metrics`, run
    once and kept by the identity a sweep's rows have (blurlab.studies.identity: the scene's
    name and content, size, shutter, reference, metrics, device, the code's digest, blurlab's
    version), with the grids and repeats: in this process, and with `cache` in a CSV file
    under cache_dir() that the sweep resumes from, so another process asking the same
    measures nothing, and an edited scene file or other code is measured anew. attrs:
    "cache_file" (or None) and "measured_at" (UTC, when the file's rows were written)."""
    settings = Settings(
        (int(size[0]), int(size[1])), None, None, tuple(metrics), repeats=SWEEP_REPEATS
    )
    grids = recommendation_grids()
    components = scene_identity(scene, settings, device_identity(ctx))
    key = row_identity({**components, "grids": grids, "repeats": SWEEP_REPEATS})
    if key not in _CACHE:
        path = None
        if cache:
            # The scene's name may come from a file: only safe characters reach the path.
            name = re.sub(r"[^\w.@-]", "_", scene.name)[:64]
            path = cache_dir() / f"{name}-{size[0]}x{size[1]}-{key}.csv"
            path.parent.mkdir(parents=True, exist_ok=True)
        table = sweep(
            ctx, [scene], grids, size, metrics=metrics, progress=progress,
            repeats=SWEEP_REPEATS, out=path,
        )  # fmt: skip
        table = table[[math.isfinite(v) for v in table["total_ms"]]].reset_index(drop=True)
        when = path.stat().st_mtime if path is not None and path.exists() else time.time()
        table.attrs["cache_file"] = None if path is None else str(path)
        table.attrs["measured_at"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(when))
        _CACHE[key] = table
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


def _question(best: str, floor: str | None, budget_ms) -> str:
    """What a recommendation answers: the cheapest row that meets `floor` (within budget_ms
    where one is given), or, without a floor, the best `best` within budget_ms."""
    if floor is None:
        return f"the best {best} within {budget_ms:g} ms"
    within = f" within {budget_ms:g} ms" if budget_ms is not None else ""
    return f"the cheapest with {floor}{within}"


def _set_question(aggregate, budget_ms, target, configurations, items, size) -> str:
    floor = f"{aggregate} >= {target:g}" if target is not None else None
    question = _question(str(aggregate), floor, budget_ms)
    return f"{question}; {configurations} configurations on {len(items)} scenes {size[0]}x{size[1]}"
