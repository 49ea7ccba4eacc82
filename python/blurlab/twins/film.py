"""A Gaussian film filter (docs/spec.md §17.6, step 4 of gather_coverage): the NumPy twin of
methods/gather_coverage/film_filter.glsl."""

from __future__ import annotations

import math

import numpy as np

from .inputs import sanitize_color


def film_radius(sigma: float) -> int:
    """The kernel's reach in px: ceil(3σ), where the Gaussian has fallen under 1.2 %."""
    return math.ceil(3 * sigma)


def film_kernel(sigma: float) -> np.ndarray:
    """The normalised 1D Gaussian of standard deviation `sigma` px at offsets -R..R, R =
    film_radius(sigma): the filter's 2D weight of (dx, dy) is the product of two of these."""
    offsets = np.arange(-film_radius(sigma), film_radius(sigma) + 1)
    weights = np.exp(-(offsets * offsets) / (2 * sigma * sigma))
    return weights / weights.sum()


def separable_filter(color, kernel) -> np.ndarray:
    """(H, W, C) float64: `color` filtered by the 2D kernel kernel[i]·kernel[k] centred on each
    pixel (an odd-length 1D `kernel`), coordinates clamped to the image."""
    color = np.asarray(color, np.float64)
    h, w = color.shape[:2]
    r = len(kernel) // 2
    offsets = np.arange(-r, r + 1)
    rows = np.clip(np.arange(h)[:, None] + offsets, 0, h - 1)  # (H, 2r+1)
    cols = np.clip(np.arange(w)[:, None] + offsets, 0, w - 1)
    out = np.zeros_like(color)
    for i, wy in enumerate(kernel):
        row = color[rows[:, i]]
        out += wy * sum(wx * row[:, cols[:, k]] for k, wx in enumerate(kernel))
    return out


def film_filter(color, sigma: float) -> np.ndarray:
    """(H, W, C) float64: each pixel the Gaussian-weighted mean (standard deviation `sigma` px)
    of the pixels within film_radius(sigma), coordinates clamped to the image; `sigma` = 0
    returns the image unchanged."""
    color = sanitize_color(color)
    if sigma <= 0:
        return color
    return separable_filter(color, film_kernel(sigma))


# film_through_taps reads a pixel through the filter as a bilinear blend that puts weight d on
# one neighbour per axis; that is a kernel only up to d = 1/2 (the pixel keeps at least half).
MAX_TAP_SPREAD = 0.5


def film_spread(sigma: float) -> float:
    """d for film_through_taps (docs/spec.md §17.6): the variance, px², of film_kernel(sigma).
    The 3-tap kernel [d/2, 1 - d, d/2] has the same variance (0.2150 at sigma = 0.5)."""
    kernel = film_kernel(sigma)
    offsets = np.arange(len(kernel)) - len(kernel) // 2
    return float((kernel * offsets * offsets).sum())


def _max_tap_sigma() -> float:
    """The largest film_filter sigma whose film_spread stays within MAX_TAP_SPREAD (bisection:
    the spread grows with sigma)."""
    low, high = 0.0, 2.0
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if film_spread(middle) <= MAX_TAP_SPREAD else (low, middle)
    return low


MAX_TAP_SIGMA = _max_tap_sigma()  # 0.708 px


# The turn of tap k (k % 4) of film_through_taps: the signs of its offset (±d, ±d) px.
TAP_TURNS = ((1, 1), (-1, -1), (1, -1), (-1, 1))


def tap_color(color, px, py, k: int, spread: float) -> np.ndarray:
    """The colour of the pixels (px, py) read through the film filter for tap k: bilinear at
    (±d, ±d) px from each pixel's centre, the signs TAP_TURNS[k % 4]; per axis weight 1 - d on
    the pixel and d on its neighbour that way, coordinates clamped to the image."""
    h, w = color.shape[:2]
    sx, sy = TAP_TURNS[k % 4]
    nx, ny = np.clip(px + sx, 0, w - 1), np.clip(py + sy, 0, h - 1)
    d = spread
    return (1 - d) * ((1 - d) * color[py, px] + d * color[py, nx]) + d * (
        (1 - d) * color[ny, px] + d * color[ny, nx]
    )


def own_color(color, spread: float) -> np.ndarray:
    """Every pixel read through the film filter as the mean of its four tap turns: the kernel
    [d/2, 1 - d, d/2] along each axis, coordinates clamped to the image."""
    return separable_filter(color, (spread / 2, 1 - spread, spread / 2))
