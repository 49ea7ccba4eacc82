"""A Gaussian film filter (docs/spec.md §17.6, step 4 of gather_coverage): the NumPy twin of
shaders/passes/film_filter.glsl."""

from __future__ import annotations

import math

import numpy as np

from .inputs import sanitize_color


def film_radius(sigma: float) -> int:
    """The kernel's reach in px: ceil(3σ), where the Gaussian has fallen under 1.2 %."""
    return math.ceil(3 * sigma)


def film_filter(color, sigma: float) -> np.ndarray:
    """(H, W, C) float64: each pixel the Gaussian-weighted mean (standard deviation `sigma` px)
    of the pixels within film_radius(sigma), coordinates clamped to the image; `sigma` = 0
    returns the image unchanged."""
    color = sanitize_color(color)
    if sigma <= 0:
        return color
    h, w = color.shape[:2]
    r = film_radius(sigma)
    offsets = np.arange(-r, r + 1)
    rows = np.clip(np.arange(h)[:, None] + offsets, 0, h - 1)  # (H, 2r+1)
    cols = np.clip(np.arange(w)[:, None] + offsets, 0, w - 1)
    out, total = np.zeros_like(color), 0.0
    for i, dy in enumerate(offsets):
        for k, dx in enumerate(offsets):
            weight = math.exp(-(dx * dx + dy * dy) / (2 * sigma * sigma))
            out += weight * color[rows[:, i]][:, cols[:, k]]
            total += weight
    return out / total
