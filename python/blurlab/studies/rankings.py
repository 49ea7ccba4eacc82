"""Rankings with confidence over many scenes (docs/spec.md §23): from a results table with one
row per (scene, contender), each contender's distribution of each metric (median with a
bootstrap interval), pairwise win rates and median differences with bootstrap intervals, the
share of scenes each contender wins, and which contender wins where over two scene features.

A contender is a method at one configuration: the `contender` column where the table has one,
else the method, or "method {params}" where a method has several configurations in the table.
Which way is better comes from the metric registry (blurlab.metrics), never from here. Every
interval is a percentile bootstrap over scenes with a fixed seed, so the same table gives the
same numbers on every run.
"""

from __future__ import annotations

import base64
import io
import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..metrics import get, registered

BOOTSTRAP_RESAMPLES = 2000
BOOTSTRAP_SEED = 0
LEVEL = 0.95  # the intervals' coverage
# The scene features (docs/spec.md §22.2) that the study report and the rankings benchmark
# draw "which method wins where" over: how fast the fastest pixels move, and how much of the
# motion is the camera's.
MAP_FEATURES = ("motion_p99", "camera_motion_share")
# The study report ranks the methods over its scenes from this many scenes on: fewer give
# intervals too wide to say anything.
RANKING_MIN_SCENES = 20
# A tie: two values closer than this share the win (half each in a pair; split in win shares).
TIE = 1e-9


def contenders(table: pd.DataFrame) -> pd.Series:
    """Each row's contender: its `contender` column, else its method, or "method {params}"
    where the table holds several configurations of that method."""
    if "contender" in table:
        return table["contender"].astype(str)
    if "method" not in table:
        raise ValueError("blurlab.rankings: the table needs a 'method' or a 'contender' column")
    if "params" not in table:
        return table["method"].astype(str)
    several = table.groupby("method")["params"].nunique()
    return pd.Series(
        [
            f"{m} {p}" if several[m] > 1 else str(m)
            for m, p in zip(table["method"], table["params"], strict=True)
        ],
        index=table.index,
    )


def best_configurations(table: pd.DataFrame, metric: str = "psnr") -> pd.DataFrame:
    """The rows of each method's one configuration with the best median `metric` over the
    scenes, among its configurations measured (finitely) on every scene of the table: a
    study's grid narrowed to one contender per method."""
    _check_metric(table, metric)
    scene_count = table["scene"].nunique()
    finite = table[np.isfinite(table[metric].astype(np.float64))]
    per_config = finite.groupby(["method", "params"], sort=False).agg(
        scenes=("scene", "nunique"), median=(metric, "median")
    )
    complete = per_config[per_config["scenes"] == scene_count].reset_index()
    if complete.empty:
        raise ValueError(f"blurlab.rankings: no configuration has a finite {metric} on every scene")
    complete["goodness"] = get(metric).goodness(complete["median"])
    best = complete.sort_values("goodness", ascending=False, kind="stable")
    best = best.drop_duplicates("method")[["method", "params"]]
    return finite.merge(best, on=["method", "params"]).drop_duplicates(["scene", "method"])


def scores(table: pd.DataFrame, metric: str) -> pd.DataFrame:
    """A scenes × contenders frame of `metric`; an error names any (scene, contender) with
    more than one row, or a scene that lacks a contender (filter the table first)."""
    _check_metric(table, metric)
    if "scene" not in table:
        raise ValueError("blurlab.rankings: the table needs a 'scene' column")
    keyed = pd.DataFrame({"scene": table["scene"], "who": contenders(table), "v": table[metric]})
    doubled = keyed.duplicated(["scene", "who"])
    if doubled.any():
        scene, who = keyed.loc[doubled, ["scene", "who"]].iloc[0]
        raise ValueError(
            f"blurlab.rankings: {who!r} has several rows on scene {scene!r}; give one row per "
            "(scene, contender): filter the table, or name contenders in a 'contender' column"
        )
    wide = keyed.pivot(index="scene", columns="who", values="v")
    missing = wide.isna()
    if missing.any().any():
        who = missing.any().idxmax()
        scene = missing[who].idxmax()
        raise ValueError(
            f"blurlab.rankings: {who!r} has no finite {metric} on scene {scene!r}; every "
            "contender needs a value on every scene it is ranked over"
        )
    return wide


def bootstrap_interval(
    values,
    statistic=np.median,
    resamples: int = BOOTSTRAP_RESAMPLES,
    seed: int = BOOTSTRAP_SEED,
    level: float = LEVEL,
) -> tuple[float, float]:
    """The percentile bootstrap interval of `statistic` over `values` (resampled with
    replacement `resamples` times from a generator seeded with `seed`)."""
    values = np.asarray(values, np.float64)
    if values.ndim != 1 or values.size == 0:
        raise ValueError("blurlab.rankings: a bootstrap needs a non-empty 1-D list of values")
    if not 0 < level < 1:
        raise ValueError(f"blurlab.rankings: level must be in (0, 1), not {level!r}")
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, values.size, size=(resamples, values.size))
    stats = statistic(values[picks], axis=1)
    tail = (1 - level) / 2 * 100
    low, high = np.percentile(stats, [tail, 100 - tail])
    return float(low), float(high)


def distributions(table: pd.DataFrame, metrics: Sequence[str] = ("psnr", "ssim", "flip")):
    """Per contender and metric (those of `metrics` the table has): the number of scenes,
    median with its bootstrap interval, mean, 10th and 90th percentiles; best median first
    within each metric."""
    rows = []
    for metric in [m for m in metrics if m in table]:
        wide = scores(table, metric)
        for who in wide:
            values = wide[who].to_numpy()
            low, high = bootstrap_interval(values)
            rows.append(
                {
                    "metric": metric,
                    "contender": who,
                    "scenes": values.size,
                    "median": float(np.median(values)),
                    "median_low": low,
                    "median_high": high,
                    "mean": float(values.mean()),
                    "p10": float(np.percentile(values, 10)),
                    "p90": float(np.percentile(values, 90)),
                }
            )
    if not rows:
        raise ValueError(f"blurlab.rankings: the table has none of the metrics {list(metrics)}")
    out = pd.DataFrame(rows)
    out["goodness"] = [
        get(m).goodness(v) for m, v in zip(out["metric"], out["median"], strict=True)
    ]
    out = out.sort_values(["metric", "goodness"], ascending=[True, False], kind="stable")
    return out.drop(columns="goodness").reset_index(drop=True)


def win_shares(table: pd.DataFrame, metric: str = "psnr") -> pd.Series:
    """The share of scenes each contender wins by `metric` (a tie splits the scene), largest
    first."""
    good = _goodness(scores(table, metric), metric)
    best = good.max(axis=1)
    winners = good.ge(best.to_numpy()[:, None] - TIE)
    shares = winners.div(winners.sum(axis=1), axis=0).sum() / len(good)
    return shares.sort_values(ascending=False, kind="stable").rename("win_share")


def pairwise(table: pd.DataFrame, metric: str = "psnr") -> pd.DataFrame:
    """Every ordered pair (a, b) of contenders over the scenes both have: the share of scenes
    where a is better (ties count half), and the median of a − b in the metric's unit with its
    paired bootstrap interval (positive: a has the higher value; the metric's direction says
    whether that is better)."""
    wide = scores(table, metric)
    good = _goodness(wide, metric)
    rows = []
    for a in wide:
        for b in wide:
            if a == b:
                continue
            margin = (good[a] - good[b]).to_numpy()
            diff = (wide[a] - wide[b]).to_numpy()
            low, high = bootstrap_interval(diff)
            rows.append(
                {
                    "a": a,
                    "b": b,
                    "scenes": diff.size,
                    "win_rate": float(((margin > TIE) + 0.5 * (abs(margin) <= TIE)).mean()),
                    "median_difference": float(np.median(diff)),
                    "difference_low": low,
                    "difference_high": high,
                }
            )
    return pd.DataFrame(rows)


def top(table: pd.DataFrame, metric: str = "psnr", n: int = 3) -> pd.DataFrame:
    """The `n` contenders with the best median `metric`: median and its interval, and the
    share of scenes each wins among all contenders."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"blurlab.rankings: n must be an integer >= 1, not {n!r}")
    ranked = distributions(table, (metric,)).head(n)
    shares = win_shares(table, metric)
    ranked["win_share"] = [float(shares[c]) for c in ranked["contender"]]
    return ranked.reset_index(drop=True)


def wins_map(
    table: pd.DataFrame, x: str, y: str, metric: str = "psnr", bins: int = 4
) -> pd.DataFrame:
    """Which contender wins where: the scenes split into `bins` × `bins` cells by the
    quantiles of scene features `x` and `y` (columns of the table, one value per scene), and
    per cell its ranges, scene count, the contender that wins most of its scenes and that
    share."""
    if isinstance(bins, bool) or not isinstance(bins, int) or bins < 1:
        raise ValueError(f"blurlab.rankings: bins must be an integer >= 1, not {bins!r}")
    features = _scene_features(table, (x, y))
    good = _goodness(scores(table, metric), metric)
    winner = good.idxmax(axis=1)
    cells = pd.DataFrame(
        {
            "x_bin": _quantile_bins(features[x], bins),
            "y_bin": _quantile_bins(features[y], bins),
            "x": features[x],
            "y": features[y],
            "winner": winner.reindex(features.index),
        }
    )
    rows = []
    for (xb, yb), cell in cells.groupby(["x_bin", "y_bin"], sort=True):
        counts = cell["winner"].value_counts().sort_index()  # a tie: the first by name
        leader = counts.idxmax()
        rows.append(
            {
                "x_bin": xb,
                "y_bin": yb,
                f"{x}_low": cell["x"].min(),
                f"{x}_high": cell["x"].max(),
                f"{y}_low": cell["y"].min(),
                f"{y}_high": cell["y"].max(),
                "scenes": len(cell),
                "winner": leader,
                "share": float(counts[leader] / len(cell)),
            }
        )
    return pd.DataFrame(rows)


def wins_map_chart(table: pd.DataFrame, x: str, y: str, metric: str = "psnr", path=None):
    """A matplotlib Figure: one point per scene at its features (x, y), coloured by the
    contender that wins it by `metric`; saved to `path` where given."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    features = _scene_features(table, (x, y))
    good = _goodness(scores(table, metric), metric)
    winner = good.idxmax(axis=1).reindex(features.index)
    fig, ax = plt.subplots(figsize=(7, 5), dpi=110)
    for i, (who, scenes) in enumerate(winner.groupby(winner, sort=True)):
        ax.scatter(
            features.loc[scenes.index, x],
            features.loc[scenes.index, y],
            s=14,
            color=plt.get_cmap("tab20")(i % 20),
            label=f"{who} ({len(scenes)})",
        )
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.set_title(f"which contender wins each scene by {get(metric).label}")
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    if path is not None:
        fig.savefig(path)
    return fig


def report_section(table: pd.DataFrame) -> str | None:
    """The study report's rankings over its scenes (HTML; the chart inline): each method at
    its configuration with the best median of the first ranked metric the table has, the top
    three per metric with 95 % intervals and win shares, every method's distribution, the top
    three pairwise, and which method wins where over MAP_FEATURES where the rows have them.
    None below RANKING_MIN_SCENES scenes."""
    ranked = [n for n in registered() if n in table and get(n).higher_is_better is not None]
    if table["scene"].nunique() < RANKING_MIN_SCENES or not ranked:
        return None
    first = ranked[0]
    chosen = best_configurations(table, first)
    # A metric some scenes lack (an HDR one on LDR scenes) ranks nothing here.
    ranked = [m for m in ranked if chosen[m].notna().all()]
    tops = pd.concat([top(chosen, m).assign(metric=m) for m in ranked], ignore_index=True)
    leaders = list(tops[tops["metric"] == first]["contender"])
    columns = ["metric", "contender", "median", "median_low", "median_high", "win_share"]
    parts = [
        f"<h2>Rankings over {table['scene'].nunique()} scenes</h2><p>Each method at its "
        f"configuration with the best median {first} over the scenes; medians with 95 % "
        "bootstrap intervals, and the share of scenes each method wins (docs/spec.md "
        "§23.1). Configurations:</p>",
        _html_table(chosen.drop_duplicates("method")[["method", "params"]]),
        "<h3>Top three by median</h3>" + _html_table(tops[columns]),
        "<h3>Every method</h3>" + _html_table(distributions(chosen, ranked)),
        f"<h3>The top three by {first}, pairwise</h3>",
        _html_table(pairwise(chosen[chosen["method"].isin(leaders)], first)),
    ]
    if all(f in chosen for f in MAP_FEATURES):
        import matplotlib.pyplot as plt

        picture = io.BytesIO()
        figure = wins_map_chart(chosen, *MAP_FEATURES, first)
        figure.savefig(picture, format="png")
        plt.close(figure)  # pyplot would keep every figure it made open
        encoded = base64.b64encode(picture.getvalue()).decode()
        parts.append(
            f"<h3>Which method wins where</h3><p><img src='data:image/png;base64,{encoded}'></p>"
            + _html_table(wins_map(chosen, *MAP_FEATURES, first))
        )
    return "".join(parts)


def _html_table(table: pd.DataFrame) -> str:
    return table.to_html(index=False, float_format=lambda v: f"{v:.4g}", border=0)


def _check_metric(table: pd.DataFrame, metric: str) -> None:
    get(metric)  # an unknown name raises, listing the registered metrics
    if metric not in table:
        raise ValueError(f"blurlab.rankings: the table has no {metric!r} column")


def _goodness(wide: pd.DataFrame, metric: str) -> pd.DataFrame:
    return get(metric).goodness(wide)


def _scene_features(table: pd.DataFrame, names) -> pd.DataFrame:
    """One row per scene of feature columns `names`; an error where one is missing or differs
    between rows of a scene."""
    for name in names:
        if name not in table:
            raise ValueError(f"blurlab.rankings: the table has no feature column {name!r}")
    per_scene = table.groupby("scene")[list(names)]
    if (per_scene.nunique(dropna=False) > 1).any().any():
        raise ValueError(f"blurlab.rankings: features {list(names)} must be one value per scene")
    features = per_scene.first()
    bad = ~np.isfinite(features.to_numpy(np.float64))
    if bad.any():
        raise ValueError(f"blurlab.rankings: features {list(names)} must be finite numbers")
    return features


def _quantile_bins(values: pd.Series, bins: int) -> pd.Series:
    """0..bins-1 by the quantiles of `values` (equal counts where the values allow)."""
    ranks = values.rank(method="first").to_numpy()
    return pd.Series(
        [min(bins - 1, math.floor((r - 1) * bins / len(values))) for r in ranks],
        index=values.index,
    )
