"""What every pass reads from a G-buffer whose values may not be finite: the NumPy twin of
shaders/common/inputs.glsl (docs/reliability.md "Non-finite input").

- color: NaN -> 0; +-inf and magnitudes beyond 2^64 -> +-2^64, per channel;
- depth: NaN, 0, negative or -inf -> +inf (far: nothing drawn there); +inf stays;
- motion: a vector with a NaN or infinite component -> zero; finite components clamped to
  +-2^20 pixels.
"""

from __future__ import annotations

import numpy as np

COLOR_LIMIT = 2.0**64
MOTION_LIMIT = 2.0**20


def sanitize_color(color) -> np.ndarray:
    c = np.asarray(color, np.float64)
    return np.clip(np.where(np.isnan(c), 0.0, c), -COLOR_LIMIT, COLOR_LIMIT)


def sanitize_depth(depth) -> np.ndarray:
    z = np.asarray(depth, np.float64)
    with np.errstate(invalid="ignore"):
        return np.where(z > 0, z, np.inf)  # NaN > 0 is False


def sanitize_motion(motion) -> np.ndarray:
    m = np.asarray(motion, np.float64)
    finite = np.isfinite(m).all(axis=-1, keepdims=True)
    return np.where(finite, np.clip(np.where(finite, m, 0.0), -MOTION_LIMIT, MOTION_LIMIT), 0.0)


# Packed filter inputs (docs/spec.md §19; GLSL twin shaders/passes/pack_inputs.comp): the
# values above, clamped into half-float range and rounded to half floats (nearest even).
HALF_MAX = 65504.0
HALF_MIN_NORMAL = 2.0**-14  # the smallest normal half: a finite depth never becomes 0


def round_to_half(x) -> np.ndarray:
    """float64 `x` as float32, then to the nearest half float (ties to even), as float64:
    shaders/common/half_float.glsl's round_to_half, finite values clamped to ±HALF_MAX as it
    clamps them (±inf stays)."""
    x = np.asarray(x, np.float32)
    x = np.where(np.isfinite(x), np.clip(x, -HALF_MAX, HALF_MAX), x)
    return x.astype(np.float16).astype(np.float64)


def pack_half(color, depth, motion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(color, depth, motion) as the packed textures hold them: sanitized, clamped to
    ±HALF_MAX (depth to [HALF_MIN_NORMAL, HALF_MAX] where finite, +inf kept), in float16."""
    c = np.clip(sanitize_color(color), -HALF_MAX, HALF_MAX)
    m = np.clip(sanitize_motion(motion), -HALF_MAX, HALF_MAX)
    z = sanitize_depth(depth)
    z = np.where(np.isfinite(z), np.clip(z, HALF_MIN_NORMAL, HALF_MAX), z)
    # Frame arrays are float32 and the clamps' bounds are exact there: one rounding, to half.
    return round_to_half(c), round_to_half(z), round_to_half(m)
