"""Whether each "auto" holds (blurlab.studies.auto_check, docs/spec.md §14): the bar, the
verdicts on a constructed table, and every rule judged on a few held-out scenes, where each
live rule must hold and each withdrawn one shows why it went."""

from __future__ import annotations

import json
import math

import pandas as pd
import pytest
from method_picks import EXAMPLE, builtin, picks

import blurlab as bl
from blurlab.studies import auto_check

# Two held-out random scenes on which the tile filters' rules lost most at 320 x 180 (the
# auto_holds record), and a built-in scene.
HELD_OUT = ["random:1000007", "random:1000030", "fan"]


def test_the_bar():
    assert auto_check.holds(-0.25, -1.0)
    assert not auto_check.holds(-0.26, 0.0)
    assert not auto_check.holds(0.0, -1.01)
    assert not auto_check.holds(math.nan, 0.0)


def test_held_out_seeds_are_above_every_fit():
    assert auto_check.held_out_scenes(2) == ["random:1000000", "random:1000001"]
    with pytest.raises(ValueError, match="held-out seeds start at 1000000"):
        auto_check.held_out_scenes(2, first=500)


def test_every_auto_rule_is_found_live_or_withdrawn():
    rules = {(r.method, r.param): r for r in auto_check.auto_parameters()}
    # k="auto" was withdrawn (docs/recommend.md): every method with k says so
    assert picks(params=("k",))
    for name in picks(params=("k",)):
        assert rules[(name, "k")].withdrawn
    # a method without a samples parameter (Godot's filter has k but none) has no samples rule
    without = [name for name in builtin() if "samples" not in bl.method(name).params]
    assert set(without) & set(picks(params=("k",)))
    for name in without:
        assert (name, "samples") not in rules
    for r in rules.values():
        p = bl.method(r.method).params[r.param]
        assert (p.auto is not None) != r.withdrawn


def test_verdicts_on_a_constructed_table():
    # k: default 20; the rule picks 8 on a (2 dB worse than 20), 20 on b and c.
    psnr = {"a": {4: 30.0, 8: 31.0, 20: 33.0}, "b": {4: 29.0, 8: 30.0, 20: 30.5},
            "c": {4: 40.0, 8: 39.0, 20: 39.5}}  # fmt: skip
    rows = [
        {"scene": s, "method": EXAMPLE, "params": json.dumps({"k": k}), "psnr": v}
        for s, values in psnr.items()
        for k, v in values.items()
    ]
    rule = auto_check.AutoRule(EXAMPLE, "k", lambda f, v: 8, False)
    chosen = {(EXAMPLE, "k"): {"a": 8, "b": 20, "c": 20}}
    verdict = auto_check.verdicts(pd.DataFrame(rows), [rule], chosen, {"k": [4, 8]}).iloc[0]
    assert verdict["auto_minus_default_median"] == 0.0
    assert verdict["auto_minus_default_worst"] == -2.0 and verdict["worst_scene"] == "a"
    assert verdict["auto_minus_best_worst"] == -2.0  # on a: 31 against 20's 33
    assert verdict["auto_minus_best_median"] == -0.5  # c: 39.5 against k = 4's 40
    assert not verdict["holds"]


def test_every_live_auto_holds_on_held_out_scenes(ctx):
    verdicts = auto_check.check(ctx, HELD_OUT, (96, 54), reference_samples=32)
    assert set(zip(verdicts["method"], verdicts["param"], strict=True)) == {
        (r.method, r.param) for r in auto_check.auto_parameters()
    }
    live = verdicts[verdicts["state"] == "live"]
    assert live["holds"].all(), live.to_string()
    # The withdrawn rules lose here too, each by more than the bar allows.
    withdrawn = verdicts[verdicts["state"] == "withdrawn"]
    assert not withdrawn["holds"].any(), withdrawn.to_string()
