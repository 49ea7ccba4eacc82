"""Does each `"auto"` hold? (docs/spec.md §14, §23.3) Every method parameter with an `"auto"`
rule, and every rule withdrawn for failing this check, is judged on scenes that no fit in
blurlab read: against the parameter's default and against each scene's best fixed value.

A rule holds when, over the scenes, its median loss to the default is at most MEDIAN_BAR_DB and
its loss on every scene at most WORST_BAR_DB. A rule that does not hold is withdrawn: the
parameter refuses `"auto"` and names what to pass instead (methods.params.WithdrawnAuto).

The rule's choice is taken from the frame that the method blurs (the scene rendered at the
method's instant, every other parameter at its default), and that value is swept beside the
fixed ones, so a withdrawn rule is judged exactly as a live one is.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..core.context import Context
from ..methods.params import Param, typed
from ..methods.registry import method, method_instant, methods, resolve_params
from ..scene import scenes
from . import auto_rules
from .sweep import sweep

MEDIAN_BAR_DB = -auto_rules.TOLERANCE_DB  # the most an "auto" may lose to the default, median
WORST_BAR_DB = auto_rules.WORST_DB  # ... and on any one scene
# Held-out random scenes start here: every fit in blurlab (the auto_rules benchmark, seeds
# 0..2A-1 with A <= 100000 by its declaration; the rankings study's first_seed defaults to 0)
# reads seeds below it.
HELD_OUT_SEED = 1_000_000
# The fixed values each kind of parameter is compared at (clipped to its range; its default
# joins them).
FIXED_VALUES = {
    "k": (4, 8, 12, 16, 20, 24, 32, 40, 48, 64),
    "samples": (5, 9, 15, 25, 31),
}


@dataclass(frozen=True)
class AutoRule:
    """One method parameter's `"auto"` rule: live (the parameter accepts "auto") or withdrawn."""

    method: str
    param: str
    rule: Callable  # rule(frame, values) -> a value, as Param.auto
    withdrawn: bool


def auto_parameters(names: Sequence[str] | None = None) -> list[AutoRule]:
    """Every parameter of methods `names` (default: all) with an "auto" rule, live or withdrawn,
    in registry and declaration order."""
    found = []
    for name in methods() if names is None else names:
        for key, p in method(name).params.items():
            if p.auto is not None:
                found.append(AutoRule(name, key, p.auto, False))
            elif p.withdrawn_auto is not None:
                found.append(AutoRule(name, key, p.withdrawn_auto.rule, True))
    return found


def held_out_scenes(count: int, first: int = HELD_OUT_SEED) -> list[str]:
    """`count` random scenes that no fit read: seeds first .. first + count - 1."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 0:
        raise ValueError(f"blurlab.auto_check: count must be an integer >= 0, not {count!r}")
    if first < HELD_OUT_SEED:
        raise ValueError(
            f"blurlab.auto_check: held-out seeds start at {HELD_OUT_SEED} or later (the fits "
            f"read the seeds below), not {first}"
        )
    return [f"random:{seed}" for seed in range(first, first + count)]


def fixed_values(key: str, p: Param, values: Sequence | None = None) -> list:
    """The fixed values parameter `key` (declared `p`) is compared at: `values` (default
    FIXED_VALUES[key]) inside its range, and its default."""
    chosen = FIXED_VALUES.get(key, ()) if values is None else values
    low = -np.inf if p.low is None else p.low
    high = np.inf if p.high is None else p.high
    inside = [v for v in chosen if low <= v <= high]
    return sorted({*inside, p.default})


def choices(ctx: Context, rules: Sequence[AutoRule], scene_names: Sequence[str], size) -> dict:
    """{(method, param): {scene: the value the rule chose}}: each scene rendered at each method's
    instant, the rule reading that frame and the method's other parameters at their defaults."""
    chosen = {(r.method, r.param): {} for r in rules}
    for scene_name in scene_names:
        scene = scenes.get(scene_name)
        frames = {}
        for r in rules:
            m = method(r.method)
            instant = method_instant(r.method)
            if instant not in frames:
                frames[instant] = ctx.render(scene, size, instant=instant)
            frame = frames[instant]
            values = resolve_params(m, frame, {})
            value = typed(r.method, r.param, r.rule(frame, values), m.params[r.param])
            chosen[(r.method, r.param)][scene_name] = value
    return chosen


def grids(rules: Sequence[AutoRule], chosen: dict, fixed: dict | None = None) -> dict:
    """The sweep's grids: per method, one part per judged parameter, varying it alone over its
    fixed values and every value its rule chose (the others at their defaults)."""
    out: dict[str, list] = {}
    for r in rules:
        p = method(r.method).params[r.param]
        base = fixed_values(r.param, p, (fixed or {}).get(r.param))
        values = sorted({*base, *chosen[(r.method, r.param)].values()})
        out.setdefault(r.method, []).append({r.param: values})
    return out


def verdicts(
    table: pd.DataFrame, rules: Sequence[AutoRule], chosen: dict, fixed: dict | None = None
) -> pd.DataFrame:
    """One row per rule: over the scenes, the rule's PSNR against the default's and against each
    scene's best fixed value (median and worst, dB; negative is a loss), the worst scene, the
    fixed value best on most scenes, and whether the rule holds."""
    rows = []
    for r in rules:
        p = method(r.method).params[r.param]
        scores = auto_rules.score_table(table, r.method)
        column = {v: json.dumps({r.param: v}) for v in {*chosen[(r.method, r.param)].values()}}
        fixed_columns = [
            json.dumps({r.param: v}) for v in fixed_values(r.param, p, (fixed or {}).get(r.param))
        ]
        picked = chosen[(r.method, r.param)]
        names = list(picked)
        auto = pd.Series([scores.at[s, column[picked[s]]] for s in names], index=names)
        default = scores.loc[names, json.dumps({r.param: p.default})]
        best = scores.loc[names, fixed_columns].max(axis=1)
        to_default = auto - default
        to_best = auto - best
        winners = scores.loc[names, fixed_columns].idxmax(axis=1).value_counts()
        median, worst = float(to_default.median()), float(to_default.min())
        rows.append(
            {
                "method": r.method,
                "param": r.param,
                "state": "withdrawn" if r.withdrawn else "live",
                "scenes": len(names),
                "auto_minus_default_median": median,
                "auto_minus_default_worst": worst,
                "worst_scene": str(to_default.idxmin()),
                "auto_minus_best_median": float(to_best.median()),
                "auto_minus_best_worst": float(to_best.min()),
                "best_fixed": json.loads(winners.index[0])[r.param],
                "holds": holds(median, worst),
            }
        )
    return pd.DataFrame(rows)


def holds(median_to_default: float, worst_to_default: float) -> bool:
    """The bar: a median loss to the default of at most 0.25 dB and at most 1 dB on any scene
    (NaN fails)."""
    return bool(
        np.isfinite(median_to_default)
        and np.isfinite(worst_to_default)
        and median_to_default >= MEDIAN_BAR_DB
        and worst_to_default >= WORST_BAR_DB
    )


def check(
    ctx: Context,
    scene_names: Sequence[str],
    size,
    rules: Sequence[AutoRule] | None = None,
    fixed: dict | None = None,
    reference_samples: int | None = None,
    out=None,
) -> pd.DataFrame:
    """verdicts() of `rules` (default: every auto_parameters()) on `scene_names` at `size`,
    PSNR against each scene's reference of `reference_samples` (None: as sweeps choose).
    `fixed`: {param: values} replacing FIXED_VALUES; `out`: a CSV the sweep resumes from."""
    rules = auto_parameters() if rules is None else list(rules)
    if not rules or not scene_names:
        raise ValueError("blurlab.auto_check: needs at least one rule and one scene")
    chosen = choices(ctx, rules, scene_names, size)
    table = sweep(
        ctx,
        scenes=list(scene_names),
        methods_and_grids=grids(rules, chosen, fixed),
        size=size,
        reference_samples=reference_samples,
        metrics=("psnr",),
        out=out,
        progress=False,
        repeats=0,  # scored, not timed
    )
    result = verdicts(table, rules, chosen, fixed)
    result.attrs["chosen"] = chosen  # {(method, param): {scene: value}}
    result.attrs["table"] = table  # the sweep's rows
    return result
