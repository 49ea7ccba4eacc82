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
