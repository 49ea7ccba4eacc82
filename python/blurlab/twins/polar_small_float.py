"""A velocity stored polar in two unsigned 11-bit floats, docs/spec.md §17.4 (GLSL twin:
shaders/common/polar_small_float.glsl): the length in pixels and the direction as a fraction of a
turn, u = atan2(v.y, v.x)/2π + 1/2 in [0, 1] (1/2 for zero motion)."""

from __future__ import annotations

import numpy as np

from .small_float import UF11_MANTISSA, quantize


def polar_codes(v: np.ndarray) -> np.ndarray:
    """(..., 2) velocities in pixels -> (..., 2) codes (length, turn), each an unsigned 11-bit
    float. Length and turn are computed in float32, as the GPU does."""
    v = np.asarray(v, np.float32)
    length = np.sqrt(np.sum(v * v, axis=-1, dtype=np.float32), dtype=np.float32)
    turn = np.arctan2(v[..., 1], v[..., 0]) / np.float32(2 * np.pi) + np.float32(0.5)
    turn = np.where((v != 0).any(axis=-1), turn, np.float32(0.5))
    return np.stack([quantize(length, UF11_MANTISSA), quantize(turn, UF11_MANTISSA)], -1)


def polar_decode(codes: np.ndarray) -> np.ndarray:
    """(..., 2) codes (length, turn) -> (..., 2) velocities in pixels."""
    angle = (codes[..., 1] - 0.5) * 2 * np.pi
    return codes[..., :1] * np.stack([np.cos(angle), np.sin(angle)], -1)
