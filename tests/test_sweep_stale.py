"""A sweep whose GPU metrics come back stale (blurlab.StaleReadback, docs/spec.md §6.3) scores
those evaluations again and returns the rows an untroubled sweep returns, in batches and one
evaluation at a time; one that stays stale fails, naming the evaluation."""

from __future__ import annotations

import pandas as pd
import pytest
from method_picks import EXAMPLE, pick

import blurlab as bl
from blurlab import metrics as m
from blurlab.metrics import queue as metric_queue

SIZE = (160, 90)
# A tile filter with k and a gather at its defaults.
GRID = {EXAMPLE: {"k": [4, 8, 12]}, pick(kind="gather", params=("taps",)): {}}
EXACT = ["scene", "method", "params", "psnr", "ssim"]


def swept(ctx, readback_batch: int, **options) -> pd.DataFrame:
    return bl.sweep(
        ctx,
        ["teapot_pass"],
        GRID,
        size=SIZE,
        reference_samples=16,
        metrics=("psnr", "ssim"),
        repeats=0,
        progress=False,
        readback_batch=readback_batch,
        **options,
    )


def stale_first(monkeypatch, owner, name: str, times: int = 1, counts=lambda *args: True) -> list:
    """Makes the first `times` calls of owner.name for which counts(*args) holds raise
    StaleReadback after doing their work (the queue is emptied, as a refused read leaves it);
    returns the list of those calls."""
    original = getattr(owner, name)
    calls = []

    def patched(*args, **kwargs):
        counted = counts(*args)
        value = original(*args, **kwargs)
        if not counted:
            return value
        calls.append(name)
        if len(calls) <= times:
            raise bl.StaleReadback("blurlab: injected: partial sums without their tickets")
        return value

    monkeypatch.setattr(owner, name, patched)
    return calls


def test_a_stale_batch_is_scored_again(ctx, monkeypatch):
    expected = swept(ctx, 4)
    # the first read of a batch that holds evaluations is refused
    calls = stale_first(
        monkeypatch, metric_queue.MetricQueue, "read", counts=lambda queue: len(queue) > 0
    )
    again = swept(ctx, 2)
    assert len(calls) == 2  # the refused batch, then the other one
    pd.testing.assert_frame_equal(again[EXACT], expected[EXACT])
    # the first batch's rows say they were scored again; the rest, and every row before, not
    assert again["stale_readbacks"].tolist() == [1, 1, 0, 0]
    assert (expected["stale_readbacks"] == 0).all()


def test_a_stale_immediate_read_is_scored_again(ctx, monkeypatch):
    expected = swept(ctx, 1)
    calls = stale_first(monkeypatch, m, "gpu_mse_ssim")
    again = swept(ctx, 1)
    assert len(calls) == len(expected) + 1  # one evaluation scored twice
    pd.testing.assert_frame_equal(again[EXACT], expected[EXACT])
    assert again["stale_readbacks"].tolist() == [1] + [0] * (len(again) - 1)


def test_an_evaluation_that_stays_stale_fails_and_says_which(ctx, monkeypatch):
    stale_first(monkeypatch, m, "gpu_mse_ssim", times=100)
    with pytest.raises(bl.StaleReadback, match="3 times in a row"):
        swept(ctx, 1)


def test_a_sweep_counts_the_batches_refused(ctx):
    assert swept(ctx, 4).attrs["stale_readbacks"] == 0


def test_a_results_file_keeps_which_rows_were_scored_again(ctx, monkeypatch, tmp_path):
    out = tmp_path / "sweep.csv"
    stale_first(monkeypatch, m, "gpu_mse_ssim", times=2)  # the first row: refused twice
    first = swept(ctx, 1, out=str(out))
    resumed = swept(ctx, 1, out=str(out))
    assert resumed.attrs["resumed"] == len(first)
    assert resumed["stale_readbacks"].tolist() == first["stale_readbacks"].tolist()
    assert resumed["stale_readbacks"].tolist() == [2] + [0] * (len(first) - 1)
