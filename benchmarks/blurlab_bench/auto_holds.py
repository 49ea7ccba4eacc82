"""The auto_holds benchmark (docs/spec.md §14, docs/recommend.md): every method parameter with
an "auto" rule, live or withdrawn, against its default and each scene's best fixed value, on
random seeds that no fit read and on the built-in scenes (blurlab.studies.auto_check)."""

from __future__ import annotations

from blurlab.methods import example_method
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies import auto_check

from .core import Benchmark, register
from .timing import split

COLUMNS = [
    ("method", ""),
    ("parameter", ""),
    ("state", ""),
    ("scenes", ""),
    ("auto − default, median", "dB"),
    ("auto − default, worst", "dB"),
    ("worst scene", ""),
    ("auto − best fixed, median", "dB"),
    ("auto − best fixed, worst", "dB"),
    ("fixed value best most often", ""),
    ("holds", ""),
]


def _rows(verdicts) -> list[list]:
    return [
        [
            v.method.removeprefix("reconstruct_"),
            v.param,
            v.state,
            v.scenes,
            v.auto_minus_default_median,
            v.auto_minus_default_worst,
            v.worst_scene,
            v.auto_minus_best_median,
            v.auto_minus_best_worst,
            v.best_fixed,
            "yes" if v.holds else "no",
        ]
        for v in verdicts.itertuples()
    ]


def _auto_holds(ctx, size, p, out) -> None:
    names = split(p["methods"]) or None
    rules = auto_check.auto_parameters(names)
    held_out = auto_check.held_out_scenes(p["held_out"], p["first_seed"])
    builtin = split(p["builtin_scenes"]) or scenes.names() + scenes.names("failure")
    every = held_out + builtin
    result = auto_check.check(
        ctx,
        every,
        size,
        rules,
        reference_samples=p["reference_samples"] or None,
        out=p["results"] or None,
    )
    chosen = result.attrs["chosen"]
    table = result.attrs["table"]
    seeds = f"{p['first_seed']}–{p['first_seed'] + p['held_out'] - 1}"
    bar = f"{-auto_check.MEDIAN_BAR_DB:g} dB and at most {-auto_check.WORST_BAR_DB:g} dB"
    out.table(
        f'every parameter with an "auto" rule: the rule against the default and each scene\'s '
        f"best fixed value, on random seeds {seeds} and the built-in scenes; it holds at a "
        f"median loss to the default of at most {bar} on any scene",
        COLUMNS,
        _rows(result),
    )
    for label, part in (("random seeds only", held_out), ("built-in scenes only", builtin)):
        picked = {key: {s: v[s] for s in part} for key, v in chosen.items()}
        out.table(f"the same, {label}", COLUMNS, _rows(auto_check.verdicts(table, rules, picked)))
    for v in result.itertuples():
        short = f"{v.method.removeprefix('reconstruct_')} {v.param}"
        out.figure(f"{short}: auto − default, median", v.auto_minus_default_median, "dB")
        out.figure(f"{short}: auto − default, worst scene", v.auto_minus_default_worst, "dB")
        out.figure(f"{short}: holds", int(v.holds), "bool")
    live = result[result["state"] == "live"]
    out.figure('live "auto" rules that hold', int(live["holds"].sum()), f"of {len(live)}")


register(
    Benchmark(
        "auto_holds",
        'every "auto" rule (live or withdrawn) against its default and the best fixed value on '
        "held-out random seeds and the built-in scenes, with the verdict of docs/spec.md §14's bar",
        {
            "held_out": Param(32, int, "random scenes that no fit read", 0, 100_000),
            "first_seed": Param(
                auto_check.HELD_OUT_SEED,
                int,
                "their first seed",
                auto_check.HELD_OUT_SEED,
                2**32 - 1 - 100_000,
            ),
            "builtin_scenes": Param(
                "", str, "comma-separated built-in scenes (empty: built-in and failure)"
            ),
            "methods": Param("", str, 'comma-separated methods (empty: every one with "auto")'),
            "reference_samples": Param(0, int, "N of each reference (0: as sweeps choose)", 0),
            "results": Param("", str, "a .csv the sweep's rows go to and resume from"),
        },
        _auto_holds,
        {"tiny": (64, 36), "software": (320, 180), "gpu": (1920, 1080)},
        {
            "tiny": {
                "held_out": 2,
                "builtin_scenes": "fan",
                "methods": example_method(),  # a tile filter with "auto" rules for k and samples
                "reference_samples": 8,
            },
            "gpu": {"held_out": 200},
        },
    )
)
