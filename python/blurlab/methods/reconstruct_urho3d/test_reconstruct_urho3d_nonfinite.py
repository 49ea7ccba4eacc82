"""reconstruct_urho3d on NaN and infinity inside its inputs (docs/reliability.md "Non-finite
input"): the GPU matches its NumPy twin on a poisoned frame (what every method shares:
tests/test_nonfinite.py)."""

from __future__ import annotations

import numpy as np
from poisoned_frames import array_frame, assert_close

import blurlab as bl

METHOD = "reconstruct_urho3d"


def test_urho3d_matches_reference_on_poisoned_input(ctx, rng):
    frame = array_frame(rng, nan_color_only=True)
    params = dict(k=8, samples=9, soft_z=0.5, exposure=1.0, seed=3, far=20.0)
    gpu = bl.blur(ctx, frame, METHOD, **params).color
    ref = bl.method(METHOD).twin_output(frame, **params)
    assert np.isfinite(gpu).all()
    assert_close(gpu, ref)
