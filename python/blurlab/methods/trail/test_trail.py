"""trail (docs/spec.md §4; spec.md here): out_n = α·C_n + (1 - α)·out_{n-1} over a frame
sequence."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl


def test_alpha_one_is_the_current_frame(ctx, rng):
    first, second = random_frame(rng, 32, 24), random_frame(rng, 32, 24)
    previous = bl.blur(ctx, first, "trail", alpha=1.0)
    out = bl.blur(ctx, second, "trail", alpha=1.0, history=previous)
    assert out.color.tobytes() == second.color.tobytes()


def test_feedback_over_a_sequence_matches_numpy(ctx, rng):
    frames = [random_frame(rng, 32, 24) for _ in range(4)]
    expected = frames[0].color.astype(np.float64)
    result = bl.blur(ctx, frames[0], "trail", alpha=0.3)
    for frame in frames[1:]:
        result = bl.blur(ctx, frame, "trail", alpha=0.3, history=result)
        expected = 0.3 * frame.color + 0.7 * expected
    np.testing.assert_allclose(result.color, expected, atol=1e-6)


@pytest.mark.parametrize("alpha", [-0.1, 1.5])
def test_alpha_outside_unit_interval(ctx, rng, alpha):
    with pytest.raises(ValueError, match=r"alpha = .* is outside \[0, 1\]"):
        bl.blur(ctx, random_frame(rng, 8, 8), "trail", alpha=alpha)
