"""The suite benchmark (docs/spec.md §26): `blurlab suite run` for every built-in method at the
device's preset, its card kept as the record: per category, each method's median with its 95 %
bootstrap interval, its rank, its win rate against the best other built-in method and its ms.
docs/leaderboard.md is generated from these records, one per device (with the suite's
version, preset and hash in the record)."""

from __future__ import annotations

import tempfile
from pathlib import Path

from blurlab.methods.params import Param
from blurlab.metrics import get
from blurlab.suite import categories, run_suite
from blurlab.suite.definition import PRESETS

from .core import Benchmark, register
from .quality import ASSETS
from .rankings import workers_of
from .timing import split

IDENTITY_TABLE = "suite identity: version, preset and content hash"


def category_table_name(name: str, primary: str) -> str:
    """A category's table in the record (docs/leaderboard.md names it)."""
    return (
        f"{name}: every built-in method at its defaults, by {primary}: median with its 95 % "
        "bootstrap interval, rank, win rate against the best other built-in method, and ms"
    )


def _suite(ctx, size, p, out) -> None:
    assets = Path(p["assets"]) if p["assets"] else (ASSETS if ASSETS.is_dir() else None)
    # The workers share this device in the single-frame categories; sequences run on ctx.
    with (
        tempfile.TemporaryDirectory(prefix="blurlab-suite-") as scratch,
        workers_of(ctx, p["workers"]) as cluster,
    ):
        card = run_suite(
            ctx,
            Path(p["out"]) if p["out"] else Path(scratch),
            split(p["methods"]) or None,
            p["preset"],
            assets=assets,
            cluster=cluster,
            pictures=False,
            field_from=p["field_from"] or None,
        )
    suite = card["suite"]
    out.table(
        IDENTITY_TABLE,
        [("version", ""), ("preset", ""), ("hash", "")],
        [[suite["version"], suite["preset"], suite["hash"]]],
    )
    measured = 0
    for category in categories():
        entry = card["categories"][category.name]
        if entry["status"] != "measured":
            continue
        measured += 1
        unit = _unit(category.primary)
        rows = []
        for name, f in sorted(entry["methods"].items(), key=lambda item: item[1]["rank"]):
            v = f["metrics"][category.primary]
            rows.append(
                [name, v["median"], v["low"], v["high"], f["rank"], f["versus"]]
                + [100 * f["win_rate"], f["ms"] if f["ms"] is not None else "–"]
            )
        out.table(
            category_table_name(category.name, category.primary),
            [("method", ""), ("median", unit), ("low", unit), ("high", unit), ("rank", "")]
            + [("against", ""), ("win rate", "%"), ("ms", "ms")],
            rows,
        )
    out.figure("methods", len(card["methods"]), "")
    out.figure("categories measured", measured, "")
    out.figure("suite run, wall", card["run"]["wall_s"], "s")
    out.figure("rows resumed or taken from the field's card", card["run"]["resumed_rows"], "")
    for name, seconds in card["run"]["category_s"].items():
        out.figure(f"{name}, wall", seconds, "s")


def _unit(metric: str) -> str:
    return get(metric).unit


register(
    Benchmark(
        "suite",
        "the suite (docs/suite.md) for every built-in method at the device's preset: per "
        "category each method's median with its 95 % bootstrap interval, rank, win rate and ms",
        {
            "preset": Param("software", PRESETS, "the suite's preset"),
            "methods": Param("", str, "comma-separated methods (empty: every single-frame one)"),
            "assets": Param("", str, "folder of the authored glTF files (empty: shared/assets)"),
            "out": Param("", str, "the card's folder, kept to resume (empty: a temporary one)"),
            "workers": Param(0, int, "local Dask workers (0: this process)", 0, 64),
            "field_from": Param(
                "", str, "an earlier card's folder whose matching rows are taken (empty: none)"
            ),
        },
        _suite,
        presets={p: {"preset": p} for p in PRESETS},
    )
)
