"""gather_weighted (docs/spec.md §4, ogldev tutorial 41; spec.md here) against its NumPy
twin."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.methods.gather_weighted import twin


def close_enough(gpu, expected):
    error = np.abs(gpu - expected).max(axis=-1)
    return (error <= 1e-3).mean() >= 0.999


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("edge", ["clamp", "ignore"])
def test_matches_reference(ctx, rng, backend, edge):
    frame = random_frame(rng, 97, 61)
    result = bl.blur(ctx, frame, "gather_weighted", backend=backend, edge=edge)
    assert close_enough(result.color, twin.gather_weighted(frame.color, frame.motion, edge=edge))


def test_zero_motion_is_the_identity(ctx, rng):
    frame = random_frame(rng, 40, 30)
    frame.motion[:] = 0
    np.testing.assert_allclose(bl.blur(ctx, frame, "gather_weighted").color, frame.color, atol=1e-6)


def test_instant_is_shutter_close():
    assert bl.method_instant("gather_weighted") == "close"
