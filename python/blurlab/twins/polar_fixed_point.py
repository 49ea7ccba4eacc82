"""A velocity in polar form with 11-bit codes and a depth rounded to a 10-bit float: the
11:11:10 texel of docs/spec.md §17.5 step 1 (engine_unreal), in NumPy. GPU twin:
shaders/common/polar_fixed_point.glsl, whose header gives the formulas.
"""

from __future__ import annotations

import numpy as np

LENGTH_CODE_MAX = 2047
ANGLE_CODES = 2048
FLOAT10_MIN = 2.0**-14  # the smallest normal 10-bit float
FLOAT10_MAX = 64512.0  # 2^15·(1 + 31/32)


def polar_codes(v: np.ndarray, radius: float) -> np.ndarray:
    """(..., 2) codes (c_l, c_a) of velocities v (pixels) against the longest length R."""
    n = np.linalg.norm(v, axis=-1)
    c_l = np.floor(np.minimum(n / radius, 1.0) * LENGTH_CODE_MAX + 0.5)
    u = np.arctan2(v[..., 1], v[..., 0]) / (2 * np.pi)
    u = np.where(u < 0, u + 1.0, u)
    c_a = np.floor(u * ANGLE_CODES + 0.5) % ANGLE_CODES
    return np.stack([c_l, np.where(n == 0, 0.0, c_a)], -1)


def decode_polar(codes: np.ndarray, radius: float) -> np.ndarray:
    """(..., 2) velocities, pixels, of codes (c_l, c_a)."""
    angle = codes[..., 1] * (2 * np.pi / ANGLE_CODES)
    length = codes[..., 0] / LENGTH_CODE_MAX * radius
    return np.stack([np.cos(angle), np.sin(angle)], -1) * length[..., None]


def float10(z) -> np.ndarray:
    """z > 0 or +inf rounded to an unsigned 10-bit float (5 exponent, 5 mantissa bits), to
    nearest even; below 2^-14 read as 2^-14, above 64512 as +inf."""
    c = np.maximum(np.asarray(z, np.float64), FLOAT10_MIN)
    finite = c <= FLOAT10_MAX
    m, e = np.frexp(np.where(finite, c, 1.0))
    q = np.ldexp(np.round(m * 64.0), e - 6)  # np.round: half to even
    return np.where(finite & (q <= FLOAT10_MAX), q, np.inf)
