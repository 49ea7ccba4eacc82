"""Reconstruct (docs/spec.md §3.4) on the GPU against its NumPy twin (twin.py), and the filter's
promises: still images unchanged, output inside the input range, no NaN."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_inside_input_range, assert_matches_twin, random_frame

import blurlab as bl


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "samples", "size"),
    [
        (20, 15, (160, 90)),
        (8, 8, (97, 61)),
        (1, 5, (40, 30)),
        (33, 16, (150, 77)),
        (64, 1, (130, 70)),
    ],
)
def test_random_frames_match_reference(ctx, rng, backend, k, samples, size):
    frame = random_frame(rng, *size, k=k)
    params = {"k": k, "samples": samples, "soft_z": 0.5, "exposure": 1.0, "seed": 7}
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", backend=backend, **params)
    options = {"jitter_tiles": 0, "adaptive_samples": 0, "early_exit": 0.0}
    assert {key: result.params[key] for key in {**params, **options}} == {**params, **options}
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("scene", ["teapot_pass", "fan", "skinned_arm"])
def test_rendered_frames_match_reference(ctx, scene):
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=12, samples=11)
    assert_matches_twin(result, frame)
    assert np.abs(result.color - frame.color).max() > 0.05  # it really blurred


def test_still_image_comes_back_unchanged(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = 0
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012")
    assert result.color.tobytes() == frame.color.tobytes()


def test_output_stays_inside_the_input_range(ctx, rng):
    frame = random_frame(rng, 120, 80)
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25  # inputs in [0.25, 0.75]
    out = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=10).color
    assert_inside_input_range(out, frame.color)


@pytest.mark.parametrize("scale", [0.0, 1e30])
def test_zero_and_huge_motion_give_no_nan(ctx, rng, scale):
    frame = random_frame(rng, 80, 60)
    frame.motion[:] = np.float32(scale) * np.sign(frame.motion)
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=8)
    assert np.isfinite(result.color).all()
    assert np.isfinite(result.buffers["tile_max"]).all()
    if scale:
        assert np.linalg.norm(result.buffers["tile_max"], axis=-1).max() == pytest.approx(8.0)


def test_same_seed_same_bits_other_seed_other_noise(ctx, rng):
    frame = random_frame(rng, 80, 60)
    a = bl.blur(ctx, frame, "reconstruct_mcguire2012", seed=3).color
    b = bl.blur(ctx, frame, "reconstruct_mcguire2012", seed=3).color
    c = bl.blur(ctx, frame, "reconstruct_mcguire2012", seed=4).color
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


def test_timings_name_every_pass_and_the_clock(ctx, rng):
    result = bl.blur(ctx, random_frame(rng, 64, 36), "reconstruct_mcguire2012")
    assert list(result.timings) == ["tile_max", "neighbor_max", "reconstruct"]
    assert result.clock == ctx.info()["timer"]
    assert result.total_ms > 0


def test_unknown_method_and_backend(ctx, rng):
    frame = random_frame(rng, 16, 16)
    with pytest.raises(ValueError, match="registered methods"):
        bl.blur(ctx, frame, "reconstruct_mcguire2021")
    with pytest.raises(ValueError, match="backends"):
        bl.blur(ctx, frame, "reconstruct_mcguire2012", backend="cuda")
    assert "reconstruct_mcguire2012" in bl.methods()


def test_untimed_blur_gives_the_same_bits(ctx, rng):
    frame = random_frame(rng, 48, 32)
    timed = bl.blur(ctx, frame, "reconstruct_mcguire2012")
    untimed = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False)
    assert untimed.color.tobytes() == timed.color.tobytes()
    assert {t.clock for t in untimed.timings.values()} == {"untimed"}
