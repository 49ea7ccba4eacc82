"""Fitting "auto" rules on some scenes and judging them on others (blurlab.studies.auto_rules,
docs/spec.md §23.3), on constructed tables whose best rule is known, and the auto_rules
benchmark's tiny preset."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import blurlab as bl
from blurlab.studies import auto_rules

K = [json.dumps({"k": k}) for k in (4, 8, 16, 32)]


def scenes_where_k_should_be_the_radius(radii) -> tuple[pd.DataFrame, pd.DataFrame]:
    """PSNR falls 1 dB per step away from the k nearest the scene's radius_p90; the other
    radii are noise that no rule should read."""
    rng = np.random.default_rng(1)
    names = [f"s{i}" for i in range(len(radii))]
    ks = np.array([4, 8, 16, 32])
    scores = pd.DataFrame(
        [40.0 - np.abs(np.arange(4) - np.argmin(np.abs(ks - r))) for r in radii],
        index=names,
        columns=K,
    )
    features = pd.DataFrame(
        {f: rng.uniform(0, 40, len(radii)) for f in auto_rules.FEATURES}, index=names
    )
    features["radius_p90"] = radii
    return scores, features


def test_the_fitted_rule_reads_the_feature_that_decides_and_generalises():
    rng = np.random.default_rng(0)
    train = scenes_where_k_should_be_the_radius(rng.uniform(2, 40, 200))
    held_out = scenes_where_k_should_be_the_radius(rng.uniform(2, 40, 200))
    rule = auto_rules.fit(*train, bins=8)
    assert rule.feature == "radius_p90"
    result = auto_rules.assess(rule, *held_out)
    # The bins' edges are quantiles, not the ks' midpoints: a few scenes near an edge lose 1 dB.
    assert result["within"] >= 0.9 and result["worst_loss"] >= -1.0
    # One fixed k is far worse: it is right on about a quarter of the scenes.
    fixed = auto_rules.assess(K[1], *held_out)
    assert fixed["within"] < 0.5 and fixed["worst_loss"] == -2.0
    assert auto_rules.meets_bar(result, builtin_margin=0.0)
    assert not auto_rules.meets_bar(result, builtin_margin=-0.3)
    assert not auto_rules.meets_bar(fixed, builtin_margin=0.0)


def test_a_rule_prints_as_its_table_and_merges_bins_that_agree():
    rule = auto_rules.RuleTable("radius_p95", (2.0, 10.0), (K[0], K[0], K[2]))
    assert [rule.choose(v) for v in (0.0, 5.0, 10.0, 99.0)] == [K[0], K[0], K[2], K[2]]
    scores, features = scenes_where_k_should_be_the_radius([3.0, 3.5, 4.0])
    single = auto_rules.fit(scores, features, bins=3)
    assert str(single) == "every frame: k = 4"
    assert "radius_p95 < 2 px: k = 4" in str(rule) and "radius_p95 >= 10 px: k = 16" in str(rule)


def test_frame_features_are_the_moving_pixels_radius_percentiles():
    motion = np.zeros((10, 10, 2), np.float32)
    motion[:5, :, 0] = 8.0  # half the pixels move 8 px: every percentile of |M|/2 is 4
    frame = bl.Frame(
        color=np.zeros((10, 10, 4), np.float32), depth=np.ones((10, 10), np.float32), motion=motion
    )
    assert auto_rules.frame_features(frame) == dict.fromkeys(auto_rules.FEATURES, 4.0)
    still = bl.Frame(color=frame.color, depth=frame.depth, motion=np.zeros_like(motion))
    assert set(auto_rules.frame_features(still).values()) == {0.0}


def test_fitting_refuses_tables_that_do_not_match():
    scores, features = scenes_where_k_should_be_the_radius([3.0, 9.0])
    with pytest.raises(ValueError, match="same non-empty scenes"):
        auto_rules.fit(scores, features.iloc[:1])
    with pytest.raises(ValueError, match="bins must be an integer >= 1"):
        auto_rules.fit(scores, features, bins=0)


def test_a_scaled_rule_takes_the_smallest_k_that_covers_the_scaled_radius():
    rules = auto_rules.scaled_rules(K)
    assert len(rules) == len(auto_rules.FEATURES) * len(auto_rules.FACTORS)
    rule = auto_rules.ScaledRule("radius_p95", 2.0, tuple(K))
    assert [rule.choose(r) for r in (0.0, 2.0, 2.5, 9.0, 100.0)] == [K[0], K[0], K[1], K[3], K[3]]
    assert str(rule) == "k = the smallest of 4, 8, 16, 32 ≥ 2 × radius_p95"
    # Configurations without k (gather_coverage's) have no scaled rule.
    assert auto_rules.scaled_rules(['{"samples": 8, "tile_percent": 3.0}']) == []


def test_a_scaled_rule_is_chosen_where_k_should_follow_the_radius_at_every_scale():
    # The best k is the smallest k >= 1.5 r, with r spread over every k: a scaled rule says
    # so exactly, where a 4-bin table cannot.
    rng = np.random.default_rng(3)
    ks = np.array([4, 8, 16, 32])
    radii = rng.uniform(0.5, 21, 300)
    names = [f"s{i}" for i in range(300)]
    best = [min(np.searchsorted(ks, 1.5 * r), 3) for r in radii]
    scores = pd.DataFrame(
        [40.0 - 1.0 * np.abs(np.arange(4) - b) for b in best], index=names, columns=K
    )
    features = pd.DataFrame({f: radii * (1 + i) for i, f in enumerate(auto_rules.FEATURES)})
    features.index = names
    rule = auto_rules.fit(scores, features)
    result = auto_rules.assess(rule, scores, features)
    assert isinstance(rule, auto_rules.ScaledRule) and result["within"] == 1.0


def test_feature_frame_measures_each_scene_as_its_own_frame_does(ctx):
    names = ["fan", "random:3", "subpixel"]
    table = auto_rules.feature_frame(ctx, names, (64, 36))
    assert list(table.index) == names and list(table.columns) == list(auto_rules.FEATURES)
    for name in names:
        frame = ctx.render(bl.scenes.get(name), (64, 36))
        assert table.loc[name].to_dict() == auto_rules.frame_features(frame)
