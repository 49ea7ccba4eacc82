"""gather_gaussian (docs/spec.md §4) on the GPU against its NumPy twin, and a gather's promises:
zero motion is the identity, the output stays inside the input range, the G-buffer instant
is the shutter's center."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_inside_input_range, random_frame
from method_picks import pick

import blurlab as bl

NAME = "gather_gaussian"


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("taps", "sigma", "edge"), [(9, 0.25, "clamp"), (2, 0.05, "ignore"), (16, 3.0, "clamp")]
)
def test_matches_reference(ctx, rng, backend, taps, sigma, edge):
    frame = random_frame(rng, 97, 61)
    result = bl.blur(ctx, frame, NAME, backend=backend, taps=taps, sigma=sigma, edge=edge)
    expected = bl.method(NAME).twin_output(frame, **result.params)
    error = np.abs(result.color - expected).max(axis=-1)
    assert (error <= 1e-3).mean() >= 0.999


def test_zero_motion_is_the_identity(ctx, rng):
    frame = random_frame(rng, 40, 30)
    frame.motion[:] = 0
    np.testing.assert_allclose(bl.blur(ctx, frame, NAME).color, frame.color, atol=1e-6)


def test_output_stays_inside_the_input_range(ctx, rng):
    frame = random_frame(rng, 64, 48)
    assert_inside_input_range(bl.blur(ctx, frame, NAME, taps=17).color, frame.color)


def test_a_wide_sigma_approaches_the_centered_box(ctx, rng):
    """σ = 10 motion lengths makes every weight within 0.13 % of the others: the box gather
    of equal taps, centered (docs/spec.md §4)."""
    frame = random_frame(rng, 64, 48)
    gauss = bl.blur(ctx, frame, NAME, taps=8, sigma=10.0).color
    # The gather of equal taps along the frame's own motion (it has a twin of the frame's
    # arrays; the one along the camera's motion has not).
    box_gather = pick(kind="gather", params=("taps", "intensity", "direction"), twin=True)
    box = bl.blur(ctx, frame, box_gather, taps=8, direction="centered").color
    assert np.abs(gauss - box).max() < 2e-3


def test_instant_is_the_shutter_center():
    assert bl.method_instant(NAME) == "center"
