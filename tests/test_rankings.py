"""Rankings with confidence (blurlab.studies.rankings, docs/spec.md §23) on constructed tables
whose answers are known."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from blurlab.studies import rankings


def table_of(values: dict[str, list[float]], metric="psnr", **features) -> pd.DataFrame:
    """One row per (scene, method): values[method][i] on scene i; features[name][i] too."""
    rows = []
    for name, column in values.items():
        for i, v in enumerate(column):
            row = {"scene": f"s{i}", "method": name, "params": "{}", metric: v}
            row.update({k: f[i] for k, f in features.items()})
            rows.append(row)
    return pd.DataFrame(rows)


def test_the_method_better_on_every_scene_wins_every_scene_and_every_pair():
    base = np.linspace(20, 40, 30)
    table = table_of({"a": list(base + 1.0), "b": list(base), "c": list(base - 2.0)})
    assert rankings.win_shares(table).to_dict() == {"a": 1.0, "b": 0.0, "c": 0.0}
    pairs = rankings.pairwise(table).set_index(["a", "b"])
    assert pairs.loc[("a", "b"), "win_rate"] == 1.0
    assert pairs.loc[("b", "a"), "win_rate"] == 0.0
    # The difference is 1 dB on every scene: the median and every bootstrap resample say so.
    row = pairs.loc[("a", "c")]
    assert row["median_difference"] == pytest.approx(3.0)
    assert row["difference_low"] == pytest.approx(3.0) and row["difference_high"] == 3.0
    top = rankings.top(table, "psnr", 2)
    assert list(top["contender"]) == ["a", "b"]
    assert top.loc[0, "win_share"] == 1.0


def test_a_lower_is_better_metric_ranks_the_lowest_first():
    table = table_of({"a": [0.1, 0.2, 0.3], "b": [0.2, 0.3, 0.4]}, metric="flip")
    assert list(rankings.top(table, "flip")["contender"]) == ["a", "b"]
    pairs = rankings.pairwise(table, "flip").set_index(["a", "b"])
    assert pairs.loc[("a", "b"), "win_rate"] == 1.0
    # a − b in FLIP's own unit: negative, which for FLIP is better.
    assert pairs.loc[("a", "b"), "median_difference"] == pytest.approx(-0.1)


def test_ties_share_the_win():
    table = table_of({"a": [30.0, 31.0], "b": [30.0, 29.0]})
    assert rankings.win_shares(table).to_dict() == {"a": 0.75, "b": 0.25}
    pairs = rankings.pairwise(table).set_index(["a", "b"])
    assert pairs.loc[("a", "b"), "win_rate"] == 0.75


def test_the_median_interval_holds_the_median_and_is_reproducible():
    rng = np.random.default_rng(5)
    values = rng.normal(30.0, 2.0, 500)
    low, high = rankings.bootstrap_interval(values)
    assert low < np.median(values) < high
    # About 2 dB spread over 500 scenes: the median is known to a few tenths of a dB.
    assert 0.05 < high - low < 0.6
    assert rankings.bootstrap_interval(values) == (low, high)
    assert rankings.bootstrap_interval(values, seed=1) != (low, high)


def test_distributions_give_each_metric_and_contender():
    table = table_of({"a": [30.0, 32.0, 34.0], "b": [20.0, 21.0, 22.0]})
    table["ssim"] = [0.9, 0.95, 0.99, 0.8, 0.85, 0.9]
    out = rankings.distributions(table, ("psnr", "ssim", "flip"))
    assert set(out["metric"]) == {"psnr", "ssim"}  # the table has no FLIP
    psnr = out[out["metric"] == "psnr"].set_index("contender")
    assert psnr.loc["a", "median"] == 32.0 and psnr.loc["b", "mean"] == 21.0
    assert psnr.index[0] == "a"


def test_several_configurations_of_a_method_are_contenders_of_their_own():
    table = pd.DataFrame(
        {
            "scene": ["s0", "s0", "s1", "s1"],
            "method": ["m", "m", "m", "m"],
            "params": ['{"k": 4}', '{"k": 8}', '{"k": 4}', '{"k": 8}'],
            "psnr": [30.0, 31.0, 30.0, 29.0],
        }
    )
    shares = rankings.win_shares(table)
    assert shares.to_dict() == {'m {"k": 4}': 0.5, 'm {"k": 8}': 0.5}


def test_the_wins_map_finds_who_wins_where():
    # a wins the slow scenes, b the fast ones; depth plays no part.
    speed = list(range(40))
    depth = [i % 5 for i in range(40)]
    a = [39.75 - s * 0.5 for s in speed]
    b = [30.0 for _ in speed]
    table = table_of({"a": a, "b": b}, speed=speed, depth=depth)
    cells = rankings.wins_map(table, "speed", "depth", bins=2)
    assert len(cells) == 4 and cells["scenes"].sum() == 40
    slow = cells[cells["x_bin"] == 0]
    fast = cells[cells["x_bin"] == 1]
    assert set(slow["winner"]) == {"a"} and set(fast["winner"]) == {"b"}
    assert (fast["share"] == 1.0).all()


def test_the_wins_map_chart_draws_a_point_per_scene(tmp_path):
    table = table_of({"a": [30.0, 20.0, 30.0], "b": [20.0, 30.0, 20.0]}, x=[1, 2, 3], y=[3, 2, 1])
    fig = rankings.wins_map_chart(table, "x", "y", path=tmp_path / "map.png")
    assert (tmp_path / "map.png").stat().st_size > 0
    assert sum(len(c.get_offsets()) for c in fig.axes[0].collections) == 3


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda t: pd.concat([t, t.iloc[:1]]), "several rows on scene"),
        (lambda t: t.iloc[1:], "has no finite psnr on scene"),
        (lambda t: t.drop(columns="psnr"), "no 'psnr' column"),
    ],
)
def test_tables_that_cannot_be_ranked_are_refused_with_the_reason(change, message):
    table = table_of({"a": [30.0, 31.0], "b": [29.0, 28.0]})
    with pytest.raises(ValueError, match=message):
        rankings.win_shares(change(table))


def test_unknown_metrics_and_features_are_refused():
    table = table_of({"a": [30.0, 31.0], "b": [29.0, 28.0]})
    with pytest.raises(ValueError, match="no metric 'sharpness'"):
        rankings.pairwise(table, "sharpness")
    with pytest.raises(ValueError, match="no feature column 'speed'"):
        rankings.wins_map(table, "speed", "depth")


def test_best_configurations_keep_each_methods_best_median_configuration_on_every_scene():
    table = pd.DataFrame(
        {
            "scene": ["s0", "s1", "s0", "s1", "s0", "s0", "s1"],
            "method": ["m", "m", "m", "m", "m", "n", "n"],
            "params": ['{"k": 4}', '{"k": 4}', '{"k": 8}', '{"k": 8}', '{"k": 16}', "{}", "{}"],
            "psnr": [30.0, 30.0, 31.0, 29.5, 50.0, 20.0, 21.0],
        }
    )
    # k = 16 was measured on one scene only; k = 8's median (30.25) beats k = 4's (30).
    kept = rankings.best_configurations(table)
    assert sorted(zip(kept["method"], kept["params"], strict=True)) == [
        ("m", '{"k": 8}'),
        ("m", '{"k": 8}'),
        ("n", "{}"),
        ("n", "{}"),
    ]
    assert rankings.win_shares(kept).to_dict() == {"m": 1.0, "n": 0.0}


def test_the_study_report_ranks_the_methods_from_twenty_scenes_on():
    rng = np.random.default_rng(2)
    speed = rng.uniform(0, 50, 20)
    table = table_of(
        {"a": list(40 - speed / 5), "b": list(np.full(20, 33.0)), "c": list(np.full(20, 20.0))},
        motion_p99=speed,
        camera_motion_share=rng.uniform(0, 1, 20),
    )
    table["ssim"] = table["psnr"] / 50
    html = rankings.report_section(table)
    assert "Rankings over 20 scenes" in html and "Which method wins where" in html
    assert "data:image/png;base64," in html
    assert rankings.report_section(table[table["scene"] != "s0"]) is None
