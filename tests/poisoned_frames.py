"""Frames with NaN, infinity, zero and negative values in their buffers, and the comparison of a
GPU output with its float64 twin where colors of 2^64 take part: for tests/test_nonfinite.py
and the methods' own tests of non-finite input (test_<name>_nonfinite.py in their folders)."""

from __future__ import annotations

import dataclasses

import numpy as np

import blurlab as bl

W, H = 48, 32


def poisoned(rng, frame: bl.Frame, fraction: float = 0.1, both_signs: bool = True) -> bl.Frame:
    """`frame` with NaN, +-inf, zero and negative values scattered through color, depth and
    motion; a rendered frame keeps its scene and camera (methods that re-render still can).
    `both_signs=False` poisons color with NaN and +inf only: sums of +2^64 and -2^64 cancel
    differently in float32 and float64, so the GPU-vs-reference comparisons avoid them."""
    color, depth, motion = frame.color.copy(), frame.depth.copy(), frame.motion.copy()
    for array, values in (
        (color, [np.nan, np.inf, -np.inf, 3e38] if both_signs else [np.nan, np.inf, 3e38]),
        (depth, [np.nan, -np.inf, 0.0, -2.0]),
        # 3e38 clamps to 2^20 px, every such vector to length k: TileMax ties ("any" may win).
        (motion, [np.nan, np.inf, -np.inf, 3e38] if both_signs else [np.nan, np.inf]),
    ):
        mask = rng.random(array.shape) < fraction
        array[mask] = rng.choice(values, int(mask.sum()))
    return dataclasses.replace(frame, color=color, depth=depth, motion=motion, textures={})


def assert_close(gpu, ref):
    """float32 against float64 where colors of 2^64 take part: a pixel that mixes in such a
    color carries float32's rounding of weights times 2^64."""
    tolerance = 2e-4 + 2e-4 * np.abs(ref) + np.where(np.abs(ref) > 1e6, 2e-6 * 2.0**64, 0.0)
    bad = np.abs(gpu - ref) > tolerance
    assert not bad.any(), f"{bad.sum()} values differ, e.g. {gpu[bad][:3]} vs {ref[bad][:3]}"


def array_frame(rng, nan_color_only: bool = False):
    from conftest import random_frame

    frame = random_frame(rng, W, H, k=8)
    frame = poisoned(rng, frame, 0.15, both_signs=False)
    if nan_color_only:  # bilinear weights of exactly 0 are ~1e-8 in float32: times 2^64 ...
        frame.color[np.abs(frame.color) > 1e6] = np.nan
    return frame
