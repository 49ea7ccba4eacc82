"""What the gathers along the motion share, docs/spec.md §4, in NumPy float64: the taps and
their edge rules (GPU: shaders/common/gather.glsl), the box gather (common/box_gather.glsl) and
the motion of the camera alone (common/camera_motion.glsl). Each method's own twin is its
folder's twin.py. A tap at continuous position p reads the pixel containing it; edge "clamp"
reads the nearest edge pixel for taps outside the image, "ignore" drops them and renormalizes
the remaining weights."""

from __future__ import annotations

import numpy as np

from .inputs import sanitize_color, sanitize_depth, sanitize_motion

EDGES = ("clamp", "ignore")


def gather_taps(color, positions, weights, edge: str) -> np.ndarray:
    """Sum of weights[i] * color at positions[i] (each (H, W, 2)), normalized."""
    if edge not in EDGES:  # "guard" re-renders the frame; on arrays it has no meaning
        raise ValueError(f"blurlab: the gathers' twins take edge {EDGES}, not {edge!r}")
    color = sanitize_color(color)
    h, w = color.shape[:2]
    total = np.zeros((h, w))
    acc = np.zeros_like(color)
    for p, weight in zip(positions, weights, strict=True):
        pixel = np.floor(p).astype(np.int64)
        inside = (
            (pixel[..., 0] >= 0) & (pixel[..., 0] < w) & (pixel[..., 1] >= 0) & (pixel[..., 1] < h)
        )
        px, py = np.clip(pixel[..., 0], 0, w - 1), np.clip(pixel[..., 1], 0, h - 1)
        use = np.full((h, w), weight) if edge == "clamp" else np.where(inside, weight, 0.0)
        acc += use[..., None] * color[py, px]
        total += use
    safe = np.where(total > 0, total, 1.0)
    return np.where(total[..., None] > 0, acc / safe[..., None], color)


def tap_centers(h: int, w: int) -> np.ndarray:
    """(H, W, 2): each pixel's center X_c, where its taps start."""
    y, x = np.mgrid[0:h, 0:w]
    return np.stack([x, y], -1) + 0.5


def box_gather(
    color, motion, *, taps: int, intensity: float, direction: str, edge: str
) -> np.ndarray:
    """The box gather ("Blurry things"): n equal taps at X - s·M·intensity, s = i/(n-1), minus
    1/2 for direction "centered" ("backward": the taps lie behind X)."""
    m = sanitize_motion(motion) * intensity
    center = tap_centers(*m.shape[:2])
    s = np.arange(taps) / (taps - 1) - (0.5 if direction == "centered" else 0.0)
    return gather_taps(color, [center - si * m for si in s], [1.0] * taps, edge)


def pixel_clip(size) -> np.ndarray:
    """(H, W, 4): each pixel center in clip space at depth 1 (ndc x, y, 1, 1)."""
    width, height = size
    ndc = tap_centers(height, width) / np.array([width, height]) * 2 - 1
    ones = np.ones(ndc.shape[:2])
    return np.stack([ndc[..., 0], ndc[..., 1], ones, ones], -1)


def camera_rotation_motion(camera: dict, size) -> np.ndarray:
    """The part of camera_motion due to the camera's rotation alone (its position held still),
    the same at every depth: the motion of points at infinity (docs/spec.md §17.4)."""
    width, height = size
    clip = pixel_clip(size)
    far = clip @ camera["sky_from_clip"].T
    direction = np.concatenate([far[..., :3] / far[..., 3:], np.zeros(far.shape[:2] + (1,))], -1)
    s0 = direction @ camera["sky_projection"][0].T
    s1 = direction @ camera["sky_projection"][1].T
    seen = (s0[..., 3] > 0) & (s1[..., 3] > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        sky = (s1[..., :2] / s1[..., 3:] - s0[..., :2] / s0[..., 3:]) * 0.5 * [width, height]
    return np.where(seen[..., None], sky, 0.0)


def world_points(depth, camera: dict, size) -> np.ndarray:
    """(H, W, 4): the world point seen at each pixel centre at its depth, from a rendered
    frame's `camera` dict (at depth 1 where the depth is infinite)."""
    depth = sanitize_depth(depth)
    ray = pixel_clip(size) @ np.linalg.inv(camera["projection"]).T
    view = ray[..., :3] / ray[..., 3:]
    scale = np.where(np.isfinite(depth), depth, 1.0) / -view[..., 2]
    view_point = np.concatenate([view * scale[..., None], np.ones(depth.shape + (1,))], -1)
    return view_point @ np.linalg.inv(camera["view"][2]).T


def camera_motion(depth, camera: dict, size) -> np.ndarray:
    """Motion from depth and the camera alone (Urho3D thesis §2.3.2): reproject each pixel's
    point to t0 and t1 with the matrices of a rendered frame's `camera` dict. Points at
    infinity move with the camera's rotation only."""
    width, height = size
    world = world_points(depth, camera, size)

    def pixels(c):
        return (c[..., :2] / np.maximum(c[..., 3:], camera["near"]) * 0.5 + 0.5) * [width, height]

    motion = pixels(world @ camera["view_projection"][1].T) - pixels(
        world @ camera["view_projection"][0].T
    )
    finite = np.isfinite(sanitize_depth(depth))
    return np.where(finite[..., None], motion, camera_rotation_motion(camera, size))
