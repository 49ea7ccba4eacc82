"""Hashed random numbers, docs/spec.md §1 "Random numbers" (GLSL twin:
shaders/common/random.glsl)."""

from __future__ import annotations

import numpy as np


def pcg(v) -> np.ndarray:
    """PCG hash of uint32 values, wrapping arithmetic."""
    with np.errstate(over="ignore"):
        v = np.asarray(v, dtype=np.uint32)
        s = v * np.uint32(747796405) + np.uint32(2891336453)
        w = ((s >> ((s >> np.uint32(28)) + np.uint32(4))) ^ s) * np.uint32(277803737)
        return (w >> np.uint32(22)) ^ w


def rand(x, y, seed) -> np.ndarray:
    """rand(x, y, seed) = pcg(x ^ pcg(y ^ pcg(seed))) / 2^32 in [0, 1), float64.

    The GPU keeps the top 24 bits of the hash (float32 cannot hold more below 1.0), so it
    differs from this value by less than 2^-24.
    """
    x = np.asarray(x, dtype=np.uint32)
    y = np.asarray(y, dtype=np.uint32)
    seed = np.asarray(seed, dtype=np.uint32)
    return pcg(x ^ pcg(y ^ pcg(seed))).astype(np.float64) / 2.0**32
