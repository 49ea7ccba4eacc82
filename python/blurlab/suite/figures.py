"""A card's figures for one category (docs/spec.md §24.3), from its rows (one per scene, or
per sequence frame, and method): each metric's median with its 95 % bootstrap interval, the
rank among the built-in methods, the win rate against the best built-in method, and the cost.
The statistics are blurlab.studies.rankings' (the same bootstrap, seed and level as the study
report and the rankings benchmark).
"""

from __future__ import annotations

import math
import statistics

import pandas as pd

from ..metrics import get
from ..studies import rankings


def finite(value) -> float | None:
    """A number for JSON: None where it is not finite (an untimed row's ms)."""
    value = float(value)
    return value if math.isfinite(value) else None


def category_figures(table: pd.DataFrame, metrics, primary: str, asked, field) -> dict:
    """{method: figures} for each method of `asked`, ranked by `primary` against `field` (the
    built-in methods, every one of which has rows in `table`)."""
    spread = rankings.distributions(table, metrics)
    by = {(r.metric, r.contender): r for r in spread.itertuples()}
    goodness = {
        name: float(get(primary).goodness(by[primary, name].median))
        for name in set(field) | set(asked)
    }
    out = {}
    for name in asked:
        others = sorted((g, n) for n, g in goodness.items() if n in field and n != name)
        rank = 1 + sum(1 for g, _ in others if g > goodness[name])
        best = others[-1][1]  # the best built-in method other than this one
        pair = rankings.pairwise(table[table["method"].isin([name, best])], primary)
        versus = pair[(pair["a"] == name) & (pair["b"] == best)].iloc[0]
        rows = table[table["method"] == name]
        out[name] = {
            "metrics": {
                metric: {
                    "median": by[metric, name].median,
                    "low": by[metric, name].median_low,
                    "high": by[metric, name].median_high,
                }
                for metric in metrics
            },
            "units": len(rows),
            "rank": rank,
            "of": len(set(field) | {name}),
            "versus": best,
            "win_rate": float(versus.win_rate),
            "difference": {
                "median": float(versus.median_difference),
                "low": float(versus.difference_low),
                "high": float(versus.difference_high),
            },
            "ms": finite(_median(rows["total_ms"])),
            "clock": next((c for c in rows["clock"] if isinstance(c, str)), None),
        }
    return out


def _median(values) -> float:
    numbers = [float(v) for v in values if math.isfinite(float(v))]
    return statistics.median(numbers) if numbers else math.nan
