"""Scoring a sweep's rows again, one at a time, in the benchmark's own process
(docs/spec.md §6.3): a check that scores made in batches and on workers are the ones an
evaluation of its own gives. `random_scenes`, `rankings` and `auto_rules` run it after their
sweeps (their `rescored` parameter)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd

from blurlab.methods.params import Param
from blurlab.studies.evaluation import STALE_COLUMN
from blurlab.studies.sweep import sweep

RESCORED = Param(8, int, "rows scored again in this process, to check the sweep's scores", 0, 1000)


def rescore_picks(table: pd.DataFrame, count: int, metric: str) -> pd.DataFrame:
    """`count` rows of a sweep's table to score again: half the rows that stand furthest from
    their group's median of `metric`, above or below, in units of the group's median absolute
    deviation (a wrong read-back has given inf, NaN and values tens of dB off either way, which
    rank first); the rest drawn from the others with a fixed seed. A row's group is its scene
    and method where the sweep has several rows of each, else its scene."""
    table = table.reset_index(drop=True)
    keys = (
        ["scene", "method"]
        if len(table) > table.groupby(["scene", "method"]).ngroups
        else ["scene"]
    )
    deviation = (table[metric] - table.groupby(keys)[metric].transform("median")).abs()
    spread = deviation.groupby([table[k] for k in keys]).transform("median")
    standing = (deviation / spread.where(spread > 0, 1.0)).fillna(np.inf)
    furthest = standing.sort_values(ascending=False, kind="stable").index[: (count + 1) // 2]
    others = table.index.difference(furthest)
    drawn = np.random.default_rng(0).permutation(others)[: count - len(furthest)]
    return table.loc[list(furthest) + list(drawn)]


def rescore(ctx, table: pd.DataFrame, size, p, metrics, out) -> None:
    """Scores p["rescored"] rows of `table` (rescore_picks, by PSNR where the sweep has it, else
    its first metric) again on `ctx`, each its own sweep of one scene, method and point at
    `size` with `metrics` and p["reference_samples"], every metric read before the next
    evaluation (readback_batch 1). Writes the count, the largest difference and the rows to
    `out`, after the sweep's own count of batches refused for missing tickets and scored again
    (table.attrs["stale_readbacks"]) and the count of the table's rows so scored (its
    STALE_COLUMN, which rows resumed from a results file keep); the rescoring is skipped where
    p["rescored"] is 0."""
    out.figure(
        "batches of GPU metrics refused (tickets missing) and scored again",
        table.attrs.get("stale_readbacks", 0),
        "batches",
    )
    if STALE_COLUMN in table:  # rows read from a results file included
        out.figure(
            "rows of the table whose GPU metrics were refused and scored again",
            int((table[STALE_COLUMN] > 0).sum()),
            "rows",
        )
    count = p["rescored"]
    if not count:
        return
    metrics = list(metrics)
    metric = "psnr" if "psnr" in metrics else metrics[0]
    rows = []
    for row in rescore_picks(table, count, metric).itertuples():
        point = {key: [value] for key, value in json.loads(row.params).items()}
        again = sweep(
            ctx,
            [row.scene],
            {row.method: point},
            size=size,
            reference_samples=p["reference_samples"] or None,
            metrics=tuple(metrics),
            repeats=0,
            progress=False,
            readback_batch=1,
        ).iloc[0]
        was = getattr(row, metric)
        # Where the scores part, whether the other metrics part too and whether the two
        # references had the same sub-frames say where to look: the frame, or the reference.
        others = max((abs(again[m] - getattr(row, m)) for m in metrics if m != metric), default=0.0)
        samples = f"{row.reference_samples} / {again['reference_samples']}"
        difference = again[metric] - was
        rows.append(
            [row.scene, row.method, row.params, was, again[metric], difference, others, samples]
        )
    out.figure("rows scored again, one evaluation at a time", len(rows), "rows")
    out.figure(
        f"largest {metric} difference of a row scored again",
        max((abs(r[5]) for r in rows), default=0.0),
        "",
    )
    out.table(
        f"rows of the sweep scored again in this process (readback_batch 1): half those furthest "
        f"from their group's median {metric} in units of its spread, half drawn at random",
        [("scene", ""), ("method", ""), ("params", ""), ("sweep", ""), ("again", "")]
        + [("again - sweep", ""), ("other metrics' largest difference", "")]
        + [("reference sub-frames, sweep / again", "")],
        rows,
    )
