"""Sequences (blurlab.temporal.sequences, docs/spec.md §21): each frame's shutter and jitter, the
references, the orders of a method and TAA, and the temporal metrics."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.temporal.sequences import ORDERS, jitter_positions, still

SIZE = (64, 36)
GATHER = next(n for n in bl.methods() if bl.method(n).kind == "gather")
RENDERS = next(n for n in bl.methods() if bl.method(n).kind == "render")


@pytest.fixture(scope="module")
def fan(ctx):
    return bl.sequence(ctx, bl.scenes.fan(), SIZE, fps=30, frames=4, reference_samples=8)


def test_each_frame_has_its_own_shutter_centred_on_its_time(fan):
    """Frame i at t_c + (i − (N − 1)/2)/fps, its shutter θ/(360·fps) long around that time."""
    centre = np.mean(bl.scenes.fan().shutter)
    assert fan.times == pytest.approx(centre + (np.arange(4) - 1.5) / 30)
    assert fan.shutters[:, 1] - fan.shutters[:, 0] == pytest.approx(np.full(4, 0.5 / 30))
    assert fan.shutters.mean(axis=1) == pytest.approx(fan.times)
    assert fan.references.shape == (4, SIZE[1], SIZE[0], 4)
    assert not np.array_equal(fan.references[0], fan.references[1])  # the fan turns


def test_the_jitter_is_halton_2_3_from_index_1():
    assert jitter_positions(3, "halton") == pytest.approx(
        np.array([[0.5, 1 / 3], [0.25, 2 / 3], [0.75, 1 / 9]])
    )
    assert np.all(jitter_positions(2, "none") == 0.5)


def test_a_frames_g_buffer_is_rendered_with_its_jitter(ctx, fan):
    frame = fan.frame(1)
    direct = ctx.render(bl.scenes.fan(), SIZE, tuple(fan.shutters[1]), jitter=fan.jitter(1))
    assert np.array_equal(frame.color, direct.color)
    assert fan.jitter(1) == pytest.approx((0.25, 0.5 - 2 / 3))


@pytest.mark.parametrize("order", ORDERS)
def test_every_order_gives_one_output_per_frame_and_scores_them(fan, order):
    run = fan.run(GATHER, order)
    assert run.color.shape == fan.references.shape and np.isfinite(run.color).all()
    assert run.scores["psnr"].shape == (4,) and np.isfinite(run.scores["psnr"]).all()
    assert 0 < run.scores["temporal_instability"] < 2
    assert run.side_by_side().shape == (4, SIZE[1], 2 * SIZE[0], 4)
    assert (run.taa_ms[1:] > 0).all() == (order != "none")


def test_the_orders_differ_where_the_scene_moves(fan):
    outputs = {order: fan.run(GATHER, order, metrics=()).color for order in ORDERS}
    assert np.array_equal(outputs["none"][0], fan.run(GATHER, "none", metrics=()).color[0])
    # The first frame has no history: TAA passes it through, after or before the blur.
    assert np.allclose(outputs["blur_then_taa"][0], outputs["none"][0], atol=1e-6)
    for a, b in [("none", "blur_then_taa"), ("blur_then_taa", "taa_then_blur")]:
        assert not np.allclose(outputs[a][-1], outputs[b][-1], atol=1e-3)


def test_methods_that_render_their_own_sub_frames_only_come_before_taa(fan):
    with pytest.raises(ValueError, match="renders its own sub-frames, so TAA cannot come before"):
        fan.run(RENDERS, "taa_then_blur")


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda ctx: bl.sequence(ctx, bl.scenes.fan(), SIZE, antialias=False), "jitter='none'"),
        (lambda ctx: bl.sequence(ctx, bl.scenes.fan(), SIZE, frames=0), "frames must be"),
        (lambda ctx: bl.sequence(ctx, bl.scenes.fan(), SIZE, fps=-1), "fps must be"),
        (lambda ctx: bl.sequence(ctx, bl.scenes.fan(), SIZE, jitter="r2"), "jitter must be"),
        (lambda ctx: bl.sequence(ctx, bl.scenes.fan(), SIZE, shutter_angle=400), "angle must"),
    ],
)
def test_bad_sequences_say_what_is_allowed(ctx, call, match):
    with pytest.raises(ValueError, match=match):
        call(ctx)


def test_bad_runs_say_what_is_allowed(fan):
    with pytest.raises(ValueError, match="order must be one of"):
        fan.run(GATHER, "taa_first")
    with pytest.raises(TypeError, match="taa has no parameter"):
        fan.run(GATHER, "blur_then_taa", taa={"alpha": 0.1})
    with pytest.raises(ValueError, match="unknown metrics"):
        fan.run(GATHER, metrics=("psnr", "vmaf"))


def test_a_held_scene_does_not_move():
    scene = still(bl.scenes.fan(), 0.01)
    obj = scene.objects[-1]
    assert np.array_equal(obj.model(0.0), obj.model(1.0))
    assert np.array_equal(scene.camera.view(0.0), scene.camera.view(1.0))


def test_temporal_instability_compares_changes_not_values():
    """|(O_i − O_{i−1}) − (R_i − R_{i−1})| averaged: an output offset by a constant is stable;
    one that flickers by ±0.1 around a still reference scores 0.2."""
    reference = np.full((3, 2, 2, 3), 0.5)
    assert bl.metrics.temporal_instability(reference, reference + 0.2) == 0.0
    flicker = reference + np.array([0.1, -0.1, 0.1])[:, None, None, None]
    assert bl.metrics.temporal_instability(reference, flicker) == pytest.approx(0.2)
    # The change is measured on colour clipped to [0, 1], as the LDR metrics see it.
    assert bl.metrics.temporal_instability(reference, reference * [[[[1]]], [[[3]]], [[[1]]]]) == (
        pytest.approx(0.5)
    )
    with pytest.raises(ValueError, match="N >= 2"):
        bl.metrics.temporal_instability(reference[0], reference[0])


def test_single_frame_sweeps_refuse_metrics_of_sequences(ctx):
    with pytest.raises(ValueError, match="measure sequences of frames, not one frame"):
        bl.sweep(ctx, ["fan"], [GATHER], SIZE, metrics=("temporal_instability",), progress=False)
