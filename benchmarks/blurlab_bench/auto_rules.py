"""The auto_rules benchmark (docs/spec.md §23.3, docs/recommend.md): for each tile filter (k
and samples) and for gather_coverage (tile size and samples), a threshold rule on a frame's
motion radius is fitted on random seeds 0..A-1, then judged on seeds A..2A-1, which it never
saw, against each scene's best fixed configuration, today's default and today's "auto" rule
where one is live (blurlab.studies.auto_check judges the withdrawn ones); and on every
built-in scene against today's default."""

from __future__ import annotations

import json

from blurlab.methods import method, methods
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies import auto_check, auto_rules

from .core import Benchmark, register
from .rankings import sweep_on_workers
from .rescore import RESCORED, rescore
from .timing import split


def tile_filters() -> list[str]:
    """The methods whose k has an "auto" rule, live or withdrawn."""
    return sorted(
        {r.method for r in auto_check.auto_parameters() if r.param == "k"},
        key=methods().index,
    )


def tile_gathers() -> list[str]:
    """The methods whose tiles are a share of the image (a `tile_percent`): gather_coverage."""
    return [n for n in methods() if "tile_percent" in method(n).params]


def _tile_gathers_named() -> str:
    """The tile gathers' names, for the benchmark's doc lines."""
    return " and ".join(tile_gathers())


def _grids(p, names: list[str]) -> dict:
    """Each method's grid: k × samples (and k = "auto") for a tile filter, tile_percent ×
    samples for a tile gather."""
    grids = {}
    for name in names:
        if name in tile_filters():
            k_values = [int(k) for k in split(p["fixed_k"])]
            samples = [int(s) for s in split(p["samples"])]
            grids[name] = [{"k": k_values, "samples": samples}]
            if method(name).params["k"].auto is not None:  # a live rule is judged too
                grids[name].append({"k": ["auto"], "samples": [15]})
        elif name in tile_gathers():
            grids[name] = {
                "tile_percent": [float(t) for t in split(p["coverage_tiles"])],
                "samples": [int(s) for s in split(p["coverage_samples"])],
            }
        else:
            raise ValueError(
                f"blurlab: auto_rules fits rules for {tile_filters() + tile_gathers()}, "
                f"not {name!r}"
            )
    return grids


def _default_config(name: str, grid) -> str:
    """Today's default configuration of the parameters `grid` varies, as a row's params JSON."""
    keys = _varied_keys(grid)
    return json.dumps({k: method(name).params[k].default for k in keys}, sort_keys=True)


def _varied_keys(grid) -> list[str]:
    first = grid if isinstance(grid, dict) else grid[0]
    return sorted(first)


def _auto_rules(ctx, size, p, out) -> None:
    filters = split(p["filters"]) or [*tile_filters(), *tile_gathers()]
    grids = _grids(p, filters)
    seeds = p["seeds"]
    train = [f"random:{s}" for s in range(seeds)]
    held_out = [f"random:{s}" for s in range(seeds, 2 * seeds)]
    builtin = split(p["builtin_scenes"]) or scenes.names()
    table = sweep_on_workers(
        ctx,
        p["workers"],
        scenes=train + held_out + builtin,
        methods_and_grids=grids,
        size=size,
        reference_samples=p["reference_samples"] or None,
        metrics=("psnr",),
        out=p["results"] or None,
        progress=False,
        repeats=0,  # scored, not timed: no warm-up or timed runs
    )
    # A record whose sweep resumed from `results` says so: its wall time is this run's alone.
    resumed = table.attrs["resumed"]
    out.figure("sweep rows read from results (evaluated by an earlier run)", resumed, "rows")
    out.figure("sweep rows evaluated in this run", len(table) - resumed, "rows")
    rescore(ctx, table, size, p, ("psnr",), out)
    features = auto_rules.feature_frame(ctx, train + held_out + builtin, size)
    summary, rules, per_builtin, by_hdr, worst = [], [], [], [], []
    # HDR emitters put most of a frame's clipped error in a few pixels of their streaks: the
    # held-out judgement is also split by them.
    hdr = {name: scenes.get(name).hdr for name in held_out}
    for name in filters:
        scores = auto_rules.score_table(table, name)
        fixed = scores[[c for c in scores if "auto" not in c]]
        default = _default_config(name, grids[name])
        if default not in fixed:
            raise ValueError(
                f"blurlab: auto_rules: the grid of {name} must hold today's default {default}"
            )
        rule = auto_rules.fit(fixed.loc[train], features.loc[train], p["bins"])
        fitted = auto_rules.assess(rule, fixed.loc[train], features.loc[train])
        judged = auto_rules.assess(rule, fixed.loc[held_out], features.loc[held_out])
        today = auto_rules.assess(default, fixed.loc[held_out], features.loc[held_out])
        short = name.removeprefix("reconstruct_")
        builtin_margins = []
        for scene in builtin:
            chosen = rule.choose(features.at[scene, rule.feature])
            margin = fixed.at[scene, chosen] - fixed.at[scene, default]
            builtin_margins.append(margin)
            per_builtin.append(
                [scene, short, fixed.at[scene, default], chosen, fixed.at[scene, chosen], margin]
            )
        worst_builtin = min(builtin_margins)
        rows = [["fitted rule", judged], [f"today's default {default}", today]]
        autos = [c for c in scores if "auto" in c]
        if autos:
            auto_loss = scores.loc[held_out, autos[0]] - fixed.loc[held_out].max(axis=1)
            rows.append([f"today's auto {autos[0]}", auto_rules.summarize(auto_loss)])
        for label, result in rows:
            summary.append(
                [
                    short,
                    label,
                    100 * result["within"],
                    result["median_loss"],
                    result["worst_loss"],
                ]
            )
        meets = auto_rules.meets_bar(judged, worst_builtin)
        # The rule's worst held-out scene, named with both configurations' PSNR, so that a
        # loss far from the others' can be rendered again and looked at.
        scene = judged["per_scene"].idxmin()
        best = fixed.loc[scene].idxmax()
        chosen = judged["chosen"][scene]
        worst.append([short, scene, chosen, fixed.at[scene, chosen], best, fixed.at[scene, best]])
        for label, result in (("fitted rule", judged), ("today's default", today)):
            for with_hdr in (True, False):
                part = result["per_scene"][[hdr[n] == with_hdr for n in held_out]]
                if part.empty:
                    continue
                split_result = auto_rules.summarize(part)
                by_hdr.append(
                    [
                        short,
                        label,
                        "with HDR emitters" if with_hdr else "without",
                        len(part),
                        100 * split_result["within"],
                        split_result["worst_loss"],
                    ]
                )
        rules.append(
            [
                short,
                str(rule),
                100 * fitted["within"],
                100 * judged["within"],
                "yes" if meets else "no",
            ]
        )
        out.figure(
            f"{short}: fitted rule within 0.25 dB on held-out seeds", 100 * judged["within"], "%"
        )
        out.figure(f"{short}: fitted rule, worst held-out loss", judged["worst_loss"], "dB")
        out.figure(
            f"{short}: today's default within 0.25 dB on held-out seeds", 100 * today["within"], "%"
        )
        out.figure(
            f"{short}: fitted rule − today's default, worst built-in scene", worst_builtin, "dB"
        )
        out.figure(f"{short}: fitted rule meets the bar", int(meets), "bool")
    out.table(
        f"the fitted rules (seeds 0–{seeds - 1}): within 0.25 dB of the best fixed configuration "
        f"on the training and the held-out seeds ({seeds}–{2 * seeds - 1}), and the bar",
        [
            ("method", ""),
            ("rule", ""),
            ("training", "%"),
            ("held out", "%"),
            ("meets the bar", ""),
        ],
        rules,
    )
    out.table(
        f"held-out seeds {seeds}–{2 * seeds - 1}: against each scene's best fixed configuration",
        [
            ("method", ""),
            ("configuration", ""),
            ("within 0.25 dB", "%"),
            ("median loss", "dB"),
            ("worst loss", "dB"),
        ],
        summary,
    )
    out.table(
        f"held-out seeds {seeds}–{2 * seeds - 1} split by whether the scene has HDR emitters",
        [
            ("method", ""),
            ("configuration", ""),
            ("scenes", ""),
            ("count", ""),
            ("within 0.25 dB", "%"),
            ("worst loss", "dB"),
        ],
        by_hdr,
    )
    out.table(
        f"each fitted rule's worst held-out scene (seeds {seeds}–{2 * seeds - 1})",
        [
            ("method", ""),
            ("scene", ""),
            ("rule's choice", ""),
            ("its PSNR", "dB"),
            ("best fixed configuration", ""),
            ("its PSNR", "dB"),
        ],
        worst,
    )
    out.table(
        "built-in scenes: the fitted rule against today's default",
        [
            ("scene", ""),
            ("method", ""),
            ("default PSNR", "dB"),
            ("rule's choice", ""),
            ("its PSNR", "dB"),
            ("rule − default", "dB"),
        ],
        per_builtin,
    )


register(
    Benchmark(
        "auto_rules",
        f"threshold rules for k and samples (tile filters) and {_tile_gathers_named()}'s tile "
        "and samples, fitted on random seeds 0..A-1 and judged on seeds A..2A-1 and the built-in "
        "scenes",
        {
            "seeds": Param(25, int, "A: fitted on seeds 0..A-1, judged on A..2A-1", 1, 100_000),
            "filters": Param("", str, "comma-separated methods (empty: tile filters + coverage)"),
            "fixed_k": Param("4,8,12,16,20,24,32,40,48,64", str, "the tile filters' k grid"),
            "samples": Param("15", str, "the tile filters' samples grid"),
            "coverage_tiles": Param("1.5,3,6", str, f"{_tile_gathers_named()}'s tile_percent grid"),
            "coverage_samples": Param("4,8,16", str, f"{_tile_gathers_named()}'s samples grid"),
            "bins": Param(4, int, "bins of the rule's threshold table", 1, 64),
            "builtin_scenes": Param("", str, "comma-separated built-in scenes (empty: all)"),
            "reference_samples": Param(0, int, "N of each reference (0: as sweeps choose)", 0),
            "results": Param("", str, "a .csv the sweep's rows go to and resume from"),
            "workers": Param(0, int, "local Dask workers (0: this process)", 0, 64),
            "rescored": RESCORED,
        },
        _auto_rules,
        {"tiny": (48, 27), "software": (320, 180), "gpu": (1920, 1080)},
        {
            "tiny": {
                "seeds": 2,
                "filters": f"{tile_filters()[0]},{tile_gathers()[0]}",  # one of each
                "fixed_k": "4,20",
                "coverage_tiles": "1.5",
                "coverage_samples": "8,16",
                "bins": 2,
                "builtin_scenes": "fan",
                "reference_samples": 8,
                "rescored": 2,
            },
            # 2 x 200 random scenes and the built-in ones, about 130 configurations each: as
            # many as an estimate of the H100's 8 minutes allows (the record's wall_s says).
            "gpu": {
                "seeds": 200,
                "fixed_k": "4,8,12,16,20,24,32,40,48,64,80,96,128",
                "samples": "9,15,25",
            },
        },
    )
)
