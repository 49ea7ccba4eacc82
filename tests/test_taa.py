"""The TAA pass (shaders/passes/taa.comp, docs/spec.md §21.2) against its NumPy twin
(blurlab.twins.taa.resolve), and what it is for: jittered frames of a still scene converge to
the antialiased reference."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.temporal.sequences import still
from blurlab.temporal.taa import PARAMS, taa, taa_values
from blurlab.twins.taa import resolve

SIZE = (160, 90)


@pytest.fixture(scope="module")
def inputs():
    """Random colour (a few non-finite values), motion up to ~10 px (some off screen) and a
    history whose counts run from 0 to 12."""
    rng = np.random.default_rng(7)
    h, w = SIZE[1], SIZE[0]
    current = rng.random((h, w, 4)).astype(np.float32) * 1.2
    current[3, 5, 0], current[7, 9, 1] = np.nan, np.inf
    motion = (rng.normal(size=(h, w, 2)) * 4).astype(np.float32)
    motion[:, :4, 0] = 12.0  # these pixels come from beyond the left edge
    history = np.concatenate([rng.random((h, w, 3)), rng.integers(0, 13, (h, w, 1))], axis=2)
    return current, motion, history.astype(np.float32)


@pytest.mark.parametrize("clip", PARAMS["clip"].kind)
@pytest.mark.parametrize("neighbourhood", PARAMS["neighbourhood"].kind)
@pytest.mark.parametrize("first", [False, True])
def test_the_taa_pass_matches_its_twin(ctx, inputs, clip, neighbourhood, first):
    current, motion, history = inputs
    values = taa_values(clip=clip, neighbourhood=neighbourhood, blend=0.125)
    given = None if first else history
    on_gpu = None if first else ctx.upload(history)
    gpu = taa(ctx, ctx.upload(current), ctx.upload(motion), on_gpu, **values)
    twin = resolve(current, motion, given, **values)
    close = np.all(np.abs(gpu.download() - twin) <= 1e-3, axis=-1)
    assert close.mean() >= 0.999, f"{(~close).sum()} pixels differ by more than 1e-3"


def test_no_history_or_an_off_screen_one_gives_the_current_frame(inputs):
    current, motion, history = inputs
    values = taa_values()
    first = resolve(current, motion, None, **values)
    assert np.array_equal(first[..., :3], np.nan_to_num(current[..., :3], posinf=2.0**64))
    resolved = resolve(current, motion, history, **values)
    off = np.arange(SIZE[0]) < 4  # their history lies 12 px to the left: off screen
    assert np.array_equal(resolved[:, off, :3], first[:, off, :3])
    assert np.all(resolved[:, off, 3] == 1.0)


def test_the_blend_runs_a_mean_until_the_history_is_full():
    """A still pixel seen as 0, 1, 0, 1, ...: w = 1/n while n < 1/blend, so the first frames
    are averaged evenly, then exponentially; the count stops at 1/blend."""
    h = None
    motion = np.zeros((1, 1, 2))
    outputs = []
    for i in range(6):
        current = np.full((1, 1, 4), float(i % 2))
        h = resolve(current, motion, h, blend=0.25, clip="none", neighbourhood="3x3")
        outputs += [h[0, 0, 0], h[0, 0, 3]]
    assert outputs[:8] == pytest.approx([0, 1, 0.5, 2, 1 / 3, 3, 0.5, 4])
    assert outputs[8:10] == pytest.approx([0.75 * 0.5, 4])  # w = max(0.25, 1/5), count kept


def test_the_history_is_held_to_the_neighbourhood():
    """A history far outside the current 3x3 box comes back to its edge (clamp) or toward its
    centre (clip) in YCoCg; "none" keeps it."""
    current = np.zeros((3, 3, 4))
    current[..., :3] = 0.2
    current[0, 0, :3] = 0.4
    history = np.ones((3, 3, 4))
    motion = np.zeros((3, 3, 2))
    out = {
        clip: resolve(current, motion, history, blend=1 / 3, clip=clip, neighbourhood="3x3")
        for clip in PARAMS["clip"].kind
    }
    # count 2: w = 1/2 between the held history and the current 0.2
    assert out["none"][1, 1, :3] == pytest.approx(0.5 * (1.0 + 0.2))
    assert out["clamp"][1, 1, :3] == pytest.approx(0.5 * (0.4 + 0.2), abs=1e-6)
    assert out["clip"][1, 1, :3] == pytest.approx(0.5 * (0.4 + 0.2), abs=1e-6)


@pytest.mark.parametrize(
    "given, match",
    [
        ({"blend": 0.0}, "blend = 0.0 must be finite and > 0 and <= 1"),
        ({"blend": 1.5}, "blend = 1.5 must be"),
        ({"clip": "clamped"}, "clip must be one of 'clip', 'clamp', 'none'"),
        ({"neighbourhood": 9}, "neighbourhood must be one of"),
        ({"alpha": 0.1}, r"taa has no parameter\(s\) \['alpha'\]"),
    ],
)
def test_bad_taa_parameters_say_what_is_allowed(given, match):
    with pytest.raises((TypeError, ValueError), match=match):
        taa_values(**given)


def test_a_history_of_another_size_is_refused(ctx):
    a, b = ctx.upload(np.zeros((4, 6, 4), np.float32)), ctx.upload(np.zeros((4, 5, 4), np.float32))
    with pytest.raises(ValueError, match="history is 5x4, the current colour 6x4"):
        taa(ctx, a, ctx.upload(np.zeros((4, 6, 2), np.float32)), b)


@pytest.fixture(scope="module")
def still_fan(ctx):
    """32 jittered frames of fan held still, and its antialiased reference (256 samples)."""
    scene = still(bl.scenes.fan(), 1 / 120)
    frames = bl.sequence(ctx, scene, SIZE, frames=32, reference_samples=1)
    reference = ctx.reference(scene, SIZE, samples=256, antialias=True, progress=False).color
    return frames, reference


def test_a_still_scene_under_taa_converges_to_the_antialiased_reference(still_fan):
    frames, reference = still_fan
    resolved = frames.run(None, "blur_then_taa", metrics=()).color
    raw = frames.run(None, "none", metrics=()).color
    assert bl.metrics.psnr(reference, resolved[-1]) >= 45.0
    assert bl.metrics.psnr(reference, raw[-1]) < 35.0  # one jittered frame alone is aliased
