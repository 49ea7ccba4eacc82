"""engine_jimenez2014 (docs/spec.md §17.8) on the GPU against its twin (twin.py) on both
backends, the talk's interleaved gradient noise, the foreground's alpha on a moving bar, and
the filter's promises: still images unchanged, output inside the input range, no NaN, same seed
same bits."""

from __future__ import annotations

import numpy as np
from conftest import assert_matches_twin, assert_timings_name

import blurlab as bl
from blurlab.methods.engine_jimenez2014 import twin as ref

METHOD = "engine_jimenez2014"


def test_interleaved_gradient_noise_is_the_talks_formula():
    y, x = np.mgrid[0:64, 0:64]
    for seed in (0, 5):
        p = np.stack([x, y], -1) + 0.5 + 5.588238 * seed
        s = p @ np.array([0.06711056, 0.00583715])
        expected = np.mod(52.9829189 * np.mod(s, 1.0), 1.0)
        noise = ref.interleaved_gradient_noise(x, y, seed)
        assert ((noise >= 0) & (noise < 1)).all()
        wrapped = np.abs(noise - expected)
        assert np.minimum(wrapped, 1 - wrapped).max() < 1e-4  # float32 against float64
    # Seeds 64 apart are the same frame of the noise; neighbours differ.
    assert (
        ref.interleaved_gradient_noise(x, y, 3) == ref.interleaved_gradient_noise(x, y, 67)
    ).all()
    assert np.abs(np.diff(ref.interleaved_gradient_noise(x, y, 0), axis=1)).min() > 0


def test_the_foreground_alpha_of_a_moving_bar(ctx):
    """A bar 8 px wide moving 32 px in x in front of a still black background: the box
    shutter's truth is the bar's coverage w/L = 1/4 over [36, 60), ramping to 0 over the 8 px
    on each side. The weight the taps leave to the pixel makes that: the background takes the
    bar where the bar's blur reaches it (grown), and the bar's own pixels show the background
    for the rest of the shutter (shrunk)."""
    width, height = 96, 20
    color = np.zeros((height, width, 4), np.float32)
    color[..., 3] = 1
    color[:, 44:52, :3] = 1.0
    depth = np.full((height, width), 10.0, np.float32)
    depth[:, 44:52] = 2.0
    motion = np.zeros((height, width, 2), np.float32)
    motion[:, 44:52, 0] = 32.0
    frame = bl.Frame(color=color, depth=depth, motion=motion)
    result = bl.blur(ctx, frame, METHOD, k=20, samples=32, soft_z=1.0)
    assert_matches_twin(result, frame)
    row = result.color[:, :, 0].mean(axis=0)
    np.testing.assert_allclose(row[36:60], 0.25, atol=0.02)  # the bar's own pixels among them
    assert (np.diff(row[28:37]) > 0).all() and (np.diff(row[59:68]) < 0).all()  # the ramps
    assert row[:27].max() == 0.0 and row[69:].max() == 0.0  # beyond its reach


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(ctx, rng, METHOD, ["tile_max", "neighbor_max", "reconstruct"])
