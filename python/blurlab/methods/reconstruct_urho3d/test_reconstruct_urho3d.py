"""reconstruct_urho3d (the Urho3D thesis's pass, docs/spec.md §3.5) against its NumPy twin."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame
from method_picks import EXAMPLE

import blurlab as bl
from blurlab.methods.reconstruct_urho3d import twin as ref


@pytest.mark.parametrize(
    ("k", "samples", "size"), [(20, 15, (160, 90)), (6, 10, (70, 50)), (1, 3, (30, 20))]
)
def test_random_frames_match_reference(ctx, rng, k, samples, size):
    frame = random_frame(rng, *size, k=k)
    params = {"k": k, "samples": samples, "soft_z": 0.5, "exposure": 1.0, "seed": 11, "far": 50.0}
    result = bl.blur(ctx, frame, "reconstruct_urho3d", **params)
    assert result.backend == "fragment"
    expected = ref.reconstruct_urho3d(frame.color, frame.depth, frame.motion, **params)
    error = np.abs(result.color - expected)
    assert (error.max(axis=-1) <= 1e-3).mean() >= 0.999
    assert error.mean() <= 1e-4


def test_rendered_frame_matches_reference_and_differs_from_mcguire(ctx):
    """The twin on a rendered frame, and a measurable difference from McGuire 2012's filter, the
    example method (EXAMPLE), on the same frame."""
    frame = ctx.render(bl.scenes.teapot_pass(), (160, 90))
    urho = bl.blur(ctx, frame, "reconstruct_urho3d", k=12)
    assert urho.params["far"] == 100.0  # the camera's far plane
    expected = ref.reconstruct_urho3d(frame.color, frame.depth, frame.motion, **urho.params)
    assert (np.abs(urho.color - expected).max(axis=-1) <= 1e-3).mean() >= 0.999
    mcguire = bl.blur(ctx, frame, EXAMPLE, k=12)
    assert np.abs(urho.color - mcguire.color).max() > 0.01  # a different filter, measurably


def test_still_image_and_finite_output(ctx, rng):
    frame = random_frame(rng, 64, 48)
    still = bl.Frame(color=frame.color, depth=frame.depth, motion=np.zeros_like(frame.motion))
    assert bl.blur(ctx, still, "reconstruct_urho3d").color.tobytes() == frame.color.tobytes()
    assert np.isfinite(bl.blur(ctx, frame, "reconstruct_urho3d").color).all()


def test_only_the_fragment_backend(ctx, rng):
    with pytest.raises(ValueError, match="backends"):
        bl.blur(ctx, random_frame(rng, 16, 16), "reconstruct_urho3d", backend="compute")
    with pytest.raises(ValueError, match="far"):
        bl.blur(ctx, random_frame(rng, 16, 16), "reconstruct_urho3d", far=-1.0)
