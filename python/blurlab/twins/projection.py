"""Pinhole projection in NumPy, docs/spec.md §1: the reference that G-buffer motion and depth are
checked against. It uses the camera's basis and field of view directly, not the 4x4 matrices
the GPU uses, so the matrices are checked too."""

from __future__ import annotations

import math

import numpy as np


def _camera_frame(camera, t: float):
    world = camera.world(t)
    return world[:3, 0], world[:3, 1], -world[:3, 2], world[:3, 3]  # right, up, forward, eye


def focal_pixels(camera, size) -> float:
    """Pixels per unit of (lateral offset / depth)."""
    return size[1] / 2 / math.tan(math.radians(camera.fov_y) / 2)


def project(points, camera, t: float, size) -> tuple[np.ndarray, np.ndarray]:
    """World points (N, 3) -> pixel positions (N, 2), x right, y down, in continuous image
    coordinates (pixel (x, y) covers [x, x+1) x [y, y+1)), and their linear depth (N,)."""
    right, up, forward, eye = _camera_frame(camera, t)
    d = np.asarray(points, dtype=np.float64) - eye
    depth = d @ forward
    f = focal_pixels(camera, size)
    x = size[0] / 2 + f * (d @ right) / depth
    y = size[1] / 2 - f * (d @ up) / depth
    return np.stack([x, y], axis=-1), depth


def unproject(pixels, depth, camera, t: float, size) -> np.ndarray:
    """Inverse of `project`: pixel positions (N, 2) and linear depths (N,) -> world points."""
    right, up, forward, eye = _camera_frame(camera, t)
    pixels = np.asarray(pixels, dtype=np.float64)
    depth = np.asarray(depth, dtype=np.float64)[..., None]
    f = focal_pixels(camera, size)
    lateral = (pixels[..., :1] - size[0] / 2) / f * right - (pixels[..., 1:] - size[1] / 2) / f * up
    return eye + depth * (forward + lateral)


def pixel_centers(width: int, height: int) -> np.ndarray:
    """(H, W, 2) centers (x + 0.5, y + 0.5)."""
    y, x = np.mgrid[0:height, 0:width] + 0.5
    return np.stack([x, y], axis=-1)
