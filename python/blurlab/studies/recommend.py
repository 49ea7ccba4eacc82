"""`bl.recommend`: which method, with which parameters, for this scene at this size and budget.

A small sweep answers it: every sweepable method on its default grid, plus the "auto" point of
each parameter that has a rule (k and samples of the tile filters), with PSNR and SSIM reduced
on the GPU. The sweep is cached per scene (name and content), device and size, so asking again
with another budget or target costs nothing. The answer is the cheapest configuration that
reaches `target_psnr`, or the most accurate one within `budget_ms`, or, with both, the cheapest
that reaches the target within the budget; the rows behind it come with it. docs/recommend.md.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field

import pandas as pd

from .. import scenes
from ..context import Context
from ..methods import method
from ..metrics import get, registered
from ..scene import Scene
from ..sizes import DEFAULT_SIZE
from .evaluation import Settings
from .identity import row_identity
from .sweep import default_grids, device_of, scene_identity, sweep

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
    if budget_ms is None and target_psnr is None:
        raise ValueError("blurlab.recommend: give budget_ms, target_psnr or both")
    for name, value in (("budget_ms", budget_ms), ("target_psnr", target_psnr)):
        if value is not None and (
            isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0
        ):
            raise ValueError(f"blurlab.recommend: {name} must be a number > 0, not {value!r}")
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
    key = row_identity(scene_identity(scene, settings, device_of(ctx)))
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
