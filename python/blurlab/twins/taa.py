"""Temporal anti-aliasing (docs/spec.md §21.2) in NumPy, float64: reproject the history by the
motion buffer, hold it to the current frame's neighbourhood in YCoCg, blend. GPU twin:
shaders/passes/taa.comp, whose header gives the same rule line by line."""

from __future__ import annotations

import numpy as np

from .inputs import sanitize_color, sanitize_motion

# YCoCg from linear RGB and back (an invertible linear map: a convex mix stays inside a box).
YCOCG = np.array([[0.25, 0.5, 0.25], [0.5, 0.0, -0.5], [-0.25, 0.5, -0.25]])
RGB_FROM_YCOCG = np.array([[1.0, 1.0, -1.0], [1.0, 0.0, 1.0], [1.0, -1.0, -1.0]])
# The pixels whose YCoCg box bounds the history, as (dx, dy) offsets.
NEIGHBOURHOODS = {
    "3x3": tuple((dx, dy) for dy in (-1, 0, 1) for dx in (-1, 0, 1)),
    "cross": ((0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)),
}
# Added to the box's half-extents before clipping, so that a flat box (every neighbour alike)
# clips to its centre without dividing by zero.
CLIP_EPSILON = 1e-6


def ycocg(rgb: np.ndarray) -> np.ndarray:
    return rgb @ YCOCG.T


def rgb_from_ycocg(yco: np.ndarray) -> np.ndarray:
    return yco @ RGB_FROM_YCOCG.T


def neighbourhood_box(current_ycocg: np.ndarray, neighbourhood: str):
    """(low, high): the per-channel YCoCg minimum and maximum over the neighbourhood, each tap
    clamped to the image (docs/spec.md §1 edges)."""
    h, w = current_ycocg.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    taps = [
        current_ycocg[np.clip(y + dy, 0, h - 1), np.clip(x + dx, 0, w - 1)]
        for dx, dy in NEIGHBOURHOODS[neighbourhood]
    ]
    return np.min(taps, axis=0), np.max(taps, axis=0)


def rectify(history_ycocg: np.ndarray, low: np.ndarray, high: np.ndarray, clip: str):
    """The history held to the box [low, high]: "clamp" per channel; "clip" moves it toward the
    box's centre along the line between them until it is inside; "none" keeps it."""
    if clip == "clamp":
        return np.clip(history_ycocg, low, high)
    if clip == "none":
        return history_ycocg
    centre = 0.5 * (low + high)
    extent = 0.5 * (high - low) + CLIP_EPSILON
    offset = history_ycocg - centre
    outside = np.max(np.abs(offset) / extent, axis=-1, keepdims=True)
    return np.where(outside > 1.0, centre + offset / np.maximum(outside, 1.0), history_ycocg)


def reprojected(history: np.ndarray, motion: np.ndarray):
    """(history at each pixel's previous position, bilinear; on-screen mask). The previous
    position of pixel X's centre is X + 0.5 − V, V the motion from the previous frame in pixels;
    off screen where it lies outside [0, W] x [0, H]."""
    h, w = history.shape[:2]
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    qx, qy = x + 0.5 - motion[..., 0], y + 0.5 - motion[..., 1]
    on_screen = (qx >= 0) & (qx <= w) & (qy >= 0) & (qy <= h)
    px, py = qx - 0.5, qy - 0.5
    x0, y0 = np.floor(px), np.floor(py)
    fx, fy = (px - x0)[..., None], (py - y0)[..., None]
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    xs = np.clip(x0, 0, w - 1), np.clip(x0 + 1, 0, w - 1)
    ys = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    top = (1 - fx) * history[ys[0], xs[0]] + fx * history[ys[0], xs[1]]
    bottom = (1 - fx) * history[ys[1], xs[0]] + fx * history[ys[1], xs[1]]
    return (1 - fy) * top + fy * bottom, on_screen


def resolve(current, motion, history, *, blend: float, clip: str, neighbourhood: str):
    """One TAA frame: (H, W, 4) with the resolved RGB and, in alpha, how many frames the
    history holds (capped at 1/blend). `history` is the previous call's output, or None on the
    first frame.

    n = max(history alpha, 0) + 1 at the reprojected position, w = max(blend, 1/n),
    out = h + w·(c − h) with h the history rectified in YCoCg. Where there is no history or it
    falls off screen, out = c and n = 1."""
    c = sanitize_color(current)[..., :3]
    v = sanitize_motion(motion)
    out = np.empty(c.shape[:2] + (4,))
    out[..., :3], out[..., 3] = c, 1.0
    if history is None:
        return out
    previous, on_screen = reprojected(sanitize_color(history), v)
    low, high = neighbourhood_box(ycocg(c), neighbourhood)
    held = rgb_from_ycocg(rectify(ycocg(previous[..., :3]), low, high, clip))
    count = np.maximum(previous[..., 3], 0.0) + 1.0
    weight = np.maximum(blend, 1.0 / count)[..., None]
    blended = held + weight * (c - held)
    out[..., :3] = np.where(on_screen[..., None], blended, c)
    out[..., 3] = np.where(on_screen, np.minimum(count, 1.0 / blend), 1.0)
    return out
