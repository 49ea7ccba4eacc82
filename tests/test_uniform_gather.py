"""The uniform class's gather (shaders/passes/uniform_gather.glsl) against
bl.twins.classify.uniform_gather, and against the full filter where motion is uniform."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.twins import classify as ref
from blurlab.twins import mcguire2012 as m


def gpu_uniform_gather(ctx, frame, k, samples, seed):
    v = m.half_velocity(frame.motion, 1.0, k)
    neighbor = m.neighbor_max(m.tile_max(v, k)).astype(np.float32)
    height, width = frame.color.shape[:2]
    color, result = ctx.upload(frame.color), ctx.empty((height, width, 4))
    ctx.shader_pass("passes/uniform_gather.glsl").run(
        {"color": color, "neighbor_max": ctx.upload(neighbor)},
        {"result": result},
        {"k": k, "samples": samples, "seed": seed},
    )
    return result.download(), neighbor


@pytest.mark.parametrize(("k", "samples", "size"), [(20, 15, (160, 90)), (7, 8, (97, 61))])
def test_matches_reference(ctx, rng, k, samples, size):
    frame = random_frame(rng, *size, k=k)
    out, neighbor = gpu_uniform_gather(ctx, frame, k, samples, seed=5)
    expected = ref.uniform_gather(frame.color, neighbor, k=k, samples=samples, seed=5)
    error = np.abs(out - expected)
    assert (error.max(axis=-1) <= 1e-3).mean() >= 0.999
    assert error.mean() <= 1e-4


def test_equals_the_full_filter_on_uniform_motion_at_one_depth(ctx, rng):
    frame = random_frame(rng, 120, 80, k=12, background=0.0)
    frame.motion[:] = (13.0, -7.0)
    frame.depth[:] = 3.0
    out, _ = gpu_uniform_gather(ctx, frame, 12, 15, seed=2)
    full = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=12, samples=15, seed=2).color
    assert np.abs(out - full).max() <= 1e-5
