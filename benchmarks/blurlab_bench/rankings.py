"""The rankings benchmark (docs/spec.md §23.1): every post-process method at its defaults on N
random scenes (docs/spec.md §22), each scene's reference and three metrics; the top three
methods by median with 95 % bootstrap intervals, the share of scenes each wins, pairwise
comparisons of the top three, and which method wins where over two scene features."""

from __future__ import annotations

import contextlib
import time

import pandas as pd

from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies import rankings
from blurlab.studies.cluster_devices import local_cluster
from blurlab.studies.sweep import sweep

from .core import Benchmark, register
from .rescore import RESCORED, rescore
from .timing import gallery_methods, post_process_methods, split


def ranked_sweep(ctx, names, size, p) -> pd.DataFrame:
    """The sweep of every chosen method at its defaults on `names`, on `ctx` or on
    p["workers"] local Dask workers, with each scene's features joined."""
    chosen = split(p["methods"]) or post_process_methods()
    arguments = {
        "scenes": names,
        "methods_and_grids": {name: {} for name in chosen},
        "size": size,
        "reference_samples": p["reference_samples"] or None,
        "metrics": tuple(split(p["metrics"])),
        "progress": False,
        "repeats": 0,  # scored, not timed: no warm-up or timed runs
    }
    table = sweep_on_workers(ctx, p["workers"], **arguments)
    return scenes.with_features(ctx, table, [scenes.get(n) for n in names], size)


@contextlib.contextmanager
def workers_of(ctx, workers: int):
    """A local cluster of `workers` Dask workers of ctx's kind of device, or None for 0 (on
    GPUs worker i takes GPU i modulo their count, so several may share one, filling the time
    one process leaves it idle while building draws and reading metrics back)."""
    if not workers:
        yield None
        return
    with local_cluster(workers, ctx.info()["device"]) as cluster:
        yield cluster


def sweep_on_workers(ctx, workers: int, **arguments) -> pd.DataFrame:
    """bl.sweep(**arguments) on `ctx` (workers = 0) or on `workers_of(ctx, workers)`."""
    with workers_of(ctx, workers) as cluster:
        return sweep(ctx if cluster is None else None, cluster=cluster, **arguments)


def _rankings(ctx, size, p, out) -> None:
    names = [f"random:{s}" for s in range(p["first_seed"], p["first_seed"] + p["scenes"])]
    start = time.perf_counter()
    table = ranked_sweep(ctx, names, size, p)
    wall = time.perf_counter() - start
    out.figure("scenes", len(names), "")
    out.figure("sweep and features, wall", wall, "s")
    rescore(ctx, table, size, p, split(p["metrics"]), out)
    metrics = [m for m in split(p["metrics"]) if m in table]
    top_rows = []
    for metric in metrics:
        top = rankings.top(table, metric, 3)
        for rank, row in enumerate(top.itertuples(), 1):
            top_rows.append(
                [metric, rank, row.contender, row.median, row.median_low, row.median_high]
                + [100 * row.win_share]
            )
            out.figure(f"{metric} #{rank}: {row.contender}, median", row.median, "")
    out.table(
        f"top three by median over {len(names)} random scenes (seeds {names[0]}…), "
        "95 % bootstrap intervals, and the share of scenes each wins among all methods",
        [("metric", ""), ("rank", ""), ("method", ""), ("median", ""), ("low", ""), ("high", "")]
        + [("wins", "%")],
        top_rows,
    )
    spread = rankings.distributions(table, metrics)
    out.table(
        "every method at its defaults: median (95 % interval), mean, 10th and 90th percentile",
        [("metric", ""), ("method", ""), ("median", ""), ("low", ""), ("high", "")]
        + [("mean", ""), ("p10", ""), ("p90", "")],
        spread[["metric", "contender", "median", "median_low", "median_high", "mean", "p10", "p90"]]
        .to_numpy()
        .tolist(),
    )
    first = metrics[0]
    leaders = list(rankings.top(table, first, 3)["contender"])
    pairs = rankings.pairwise(table[table["method"].isin(leaders)], first)
    out.table(
        f"the top three by {first}, pairwise: a's win rate over b and median a − b (95 % interval)",
        [("a", ""), ("b", ""), ("a wins", "%"), ("median a − b", "")] + [("low", ""), ("high", "")],
        [
            [r.a, r.b, 100 * r.win_rate, r.median_difference, r.difference_low, r.difference_high]
            for r in pairs.itertuples()
        ],
    )
    x, y = split(p["map_features"])
    cells = rankings.wins_map(table, x, y, first, p["bins"])
    out.table(
        f"which method wins where by {first}: scenes split into {p['bins']}×{p['bins']} cells "
        f"by the quantiles of {x} and {y}",
        [(f"{x} from", ""), (f"{x} to", ""), (f"{y} from", ""), (f"{y} to", "")]
        + [("scenes", ""), ("wins most", ""), ("its share", "%")],
        [
            [c[f"{x}_low"], c[f"{x}_high"], c[f"{y}_low"], c[f"{y}_high"], c["scenes"]]
            + [c["winner"], 100 * c["share"]]
            for c in cells.to_dict("records")
        ],
    )


register(
    Benchmark(
        "rankings",
        "every post-process method at its defaults on N random scenes: the top three by median "
        "PSNR, SSIM and FLIP with 95 % bootstrap intervals, win shares, pairwise comparisons and "
        "which method wins where",
        {
            "scenes": Param(200, int, "N random scenes", 2, 100_000),
            "first_seed": Param(0, int, "the first seed (seeds first_seed .. + N - 1)", 0),
            "methods": Param("", str, "comma-separated methods (empty: every post-process)"),
            "metrics": Param("psnr,ssim,flip", str, "comma-separated metrics (first: the map)"),
            "map_features": Param(
                ",".join(rankings.MAP_FEATURES), str, "the two scene features of the wins map"
            ),
            "bins": Param(4, int, "cells per feature of the wins map", 1, 64),
            "workers": Param(0, int, "local Dask workers (0: this process)", 0, 64),
            "reference_samples": Param(0, int, "N of each reference (0: as sweeps choose)", 0),
            "rescored": RESCORED,
        },
        _rankings,
        {"tiny": (48, 27), "software": (160, 90), "gpu": (1920, 1080)},
        {
            "tiny": {
                "scenes": 3,
                # a gather and a tile filter
                "methods": f"{gallery_methods('gather')[0]},{gallery_methods('filter')[0]}",
                "metrics": "psnr",
                "bins": 1,
                "reference_samples": 8,
                "rescored": 2,
            },
            "gpu": {"scenes": 500},
        },
    )
)
