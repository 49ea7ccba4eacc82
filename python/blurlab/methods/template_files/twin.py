"""The NumPy twin of my_tent: spec.md in code, float64; the shader agrees with it."""

import numpy as np

from blurlab.twins.inputs import sanitize_color, sanitize_motion


def my_tent(color, motion, *, taps: int, scale: float) -> np.ndarray:
    c = sanitize_color(color)
    m = sanitize_motion(motion) * scale
    height, width = c.shape[:2]
    ys, xs = np.mgrid[0:height, 0:width]
    center = np.stack([xs + 0.5, ys + 0.5], -1)
    total = np.zeros_like(c)
    weights = 0.0
    for i in range(taps):
        s = (i + 0.5) / taps - 0.5
        weight = 1.0 - 2.0 * abs(s)
        p = np.floor(center - s * m)
        x = np.clip(p[..., 0], 0, width - 1).astype(np.int64)
        y = np.clip(p[..., 1], 0, height - 1).astype(np.int64)
        total += weight * c[y, x]
        weights += weight
    return total / weights
