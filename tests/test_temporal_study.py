"""The summaries of the temporal study (blurlab.studies.temporal): which order wins, ties, where
the winner flips, and how far a method's error departs from what the shutter implies."""

from __future__ import annotations

import pandas as pd
import pytest

from blurlab.studies import temporal


def rows(scene, method, **psnr_by_order):
    return [
        {"scene": scene, "method": method, "order": order, "psnr": p, "temporal_instability": 0.1}
        for order, p in psnr_by_order.items()
    ]


def test_the_winner_its_margin_ties_and_flips():
    table = pd.DataFrame(
        rows("a", "f", none=30.0, blur_then_taa=33.0, taa_then_blur=34.0)
        + rows("b", "f", none=30.0, blur_then_taa=35.0, taa_then_blur=34.5)
        + rows("c", "f", none=30.0, blur_then_taa=34.0, taa_then_blur=34.005)  # a tie
        + rows("a", temporal.NO_METHOD, none=20.0, blur_then_taa=40.0)  # not a method
    )
    summary = temporal.orders_summary(table)
    winner = summary["winners"].set_index("method").loc["f"]
    assert winner["best"] == "taa_then_blur"  # medians 34.005 against 34.0 and 30.0
    assert winner["margin_db"] == pytest.approx(0.005)
    assert winner["flips"] == "b (blur_then_taa)"  # c is a tie, which includes the winner
    wins = summary["wins"]["psnr"]
    assert (wins["taa_then_blur"], wins["blur_then_taa"], wins["none"]) == (2, 2, 0)
    assert wins.sum() == 4  # every stability value ties: all 3 orders on 3 scenes
    assert summary["wins"]["temporal_instability"].sum() == 9


def test_relative_error_spread_is_one_when_the_error_follows_the_shutter():
    table = pd.DataFrame(
        [
            {"scene": "s", "method": m, "order": "none", "fps": fps, "psnr": 30.0}
            | {"temporal_instability": 0.0, "relative_mse": r}
            for m, fps, r in [("even", 30, 0.5), ("even", 60, 0.5), ("drifts", 30, 0.5)]
            + [("drifts", 60, 1.0)]
        ]
    )
    spread = temporal.frame_rate_summary(table).groupby("method")["relative_mse_spread"].first()
    assert spread["even"] == pytest.approx(1.0) and spread["drifts"] == pytest.approx(2.0)
