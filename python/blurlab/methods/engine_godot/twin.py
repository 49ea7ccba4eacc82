"""engine_godot, docs/spec.md §17.10, in NumPy float64: the motion blur that Godot's motion-blur
pull request (godotengine/godot#115027) and its addon describe, written from that design. One
function per pass; the GPU passes (velocity.glsl and reconstruct.glsl beside this file,
shaders/passes/tile_max.glsl and neighbor_max.glsl) must match them.
"""

from __future__ import annotations

import numpy as np

from ...twins.gathers import camera_motion, camera_rotation_motion, pixel_clip, world_points
from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth, sanitize_motion
from ...twins.mcguire2012 import (
    cone,
    cylinder,
    exits_early,
    half_velocity,
    len_half,
    length_key,
    neighbor_max,
    soft_depth_compare,
    tile_max,
)

SAMPLES_BY_QUALITY = {"low": 4, "medium": 8, "high": 16}  # the addon's quality presets
FRAMERATE_MODES = ("native", "capped", "fixed")
# TileMax and NeighborMax compare lengths in 1/64 px steps (shaders/common/length_key.glsl):
# velocities clamped to the tile size are equal lengths, which the first in row order wins.
LENGTH_KEY_STEPS = 64
FLIP_GUARD = 1e-3  # without the near-plane correction, |w| >= this x near before dividing


def framerate_scale(framerate_mode: str, fps: float, reference_fps: float) -> float:
    """§17.10 step 1: the factor on the frame's motion. native: 1 (the frame's own motion);
    fixed: fps / reference_fps (as long as a frame at the reference rate would blur); capped:
    the smaller of the two (never longer than at the reference rate)."""
    ratio = fps / reference_fps
    return {"native": 1.0, "fixed": ratio, "capped": min(1.0, ratio)}[framerate_mode]


def near_clipped(end: np.ndarray, instant: np.ndarray, near: float) -> np.ndarray:
    """The clip position `end` moved back along the segment from `instant` to the point where
    the segment meets the near plane (w = near), where `end` lies closer than it."""
    span = instant[..., 3] - end[..., 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.nan_to_num(np.clip((instant[..., 3] - near) / span, 0.0, 1.0))
    behind = end[..., 3] < near
    return np.where(behind[..., None], instant + s[..., None] * (end - instant), end)


def camera_parts(depth, camera: dict, size, near_correction: bool):
    """§17.10 step 1: per pixel (camera motion, its depth change over the shutter), pixels and
    depth units. With `near_correction` an end of the shutter at which the pixel's point lies
    closer than the near plane is moved back to where it crossed that plane; without it each
    end is divided by its own w, as a velocity buffer computed without clipping does, so a
    point behind the eye is flipped through the image centre (|w| kept at least FLIP_GUARD·near).
    Points at infinity move with the rotation and keep their depth."""
    z = sanitize_depth(depth)
    finite = np.isfinite(z)
    world = world_points(depth, camera, size)
    ends = [world @ camera["view_projection"][i].T for i in (0, 1)]
    near = camera["near"]
    if near_correction:
        zf = np.where(finite, z, 1.0)
        clip = pixel_clip(size)
        instant = np.stack([clip[..., 0] * zf, clip[..., 1] * zf, zf, zf], -1)
        ends = [near_clipped(end, instant, near) for end in ends]
    width, height = size

    def pixels(c):
        w = c[..., 3:]
        if near_correction:
            w = np.maximum(w, near)
        else:
            guard = FLIP_GUARD * near
            w = np.where(np.abs(w) < guard, np.where(w < 0, -guard, guard), w)
        return (c[..., :2] / w * 0.5 + 0.5) * [width, height]

    motion = pixels(ends[1]) - pixels(ends[0])
    dz = ends[1][..., 3] - ends[0][..., 3]
    motion = np.where(finite[..., None], motion, camera_rotation_motion(camera, size))
    return motion, np.where(finite, dz, 0.0)


def velocity(
    depth,
    motion,
    camera: dict | None,
    *,
    rotation_multiplier: float,
    translation_multiplier: float,
    object_multiplier: float,
    clamp_to_original: bool,
    near_correction: bool,
    depth_velocity: bool,
    framerate_mode: str,
    fps: float,
    reference_fps: float,
) -> np.ndarray:
    """§17.10 step 1: (H, W, 4): the velocity V (pixels, over the shutter), the depth and the
    depth velocity dz. V = r·rotation + t·translation + o·object, the camera's parts from depth
    and the camera's transforms, the object's the rest of the G-buffer's motion; clamped to
    max(r, t, o)·|original|; both scaled by the frame-rate mode. A frame without a camera has
    object motion only."""
    m = sanitize_motion(motion)
    z = sanitize_depth(depth)
    size = (m.shape[1], m.shape[0])
    if camera is None:
        v, dz = object_multiplier * m, np.zeros(z.shape)
    else:
        whole, dz = camera_parts(depth, camera, size, near_correction)
        rotation = camera_rotation_motion(camera, size)
        obj = m - camera_motion(depth, camera, size)
        v = (
            rotation_multiplier * rotation
            + translation_multiplier * (whole - rotation)
            + object_multiplier * obj
        )
        dz = translation_multiplier * dz
        if clamp_to_original:
            largest = max(rotation_multiplier, translation_multiplier, object_multiplier)
            limit = largest * np.linalg.norm(whole + obj, axis=-1)
            n = np.linalg.norm(v, axis=-1)
            with np.errstate(divide="ignore", invalid="ignore"):
                shrink = np.where(n > limit, limit / n, 1.0)
            v = v * shrink[..., None]
    scale = framerate_scale(framerate_mode, fps, reference_fps)
    dz = dz * scale if depth_velocity else np.zeros(z.shape)
    return np.concatenate([v * scale, z[..., None], dz[..., None]], -1)


def reconstruct(color, vel, neighbor, *, k: int, exposure: float, soft_z: float, taps, seed):
    """§17.10 step 3: `taps` samples centred on X along the neighbourhood's half-vector vN,
    t_i = -1 + 2(i + j + 1)/(taps + 1), weighted as §3.4 weighs them, the two depths compared
    at the tap's time t/2 of the shutter: z + (t/2)·dz."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    v = half_velocity(vel[..., :2], exposure, k)
    z, dz = vel[..., 2], vel[..., 3] * exposure
    y, x = np.mgrid[0:h, 0:w]
    vn = neighbor[y // k, x // k]
    moving = ~exits_early(np.linalg.norm(vn, axis=-1), 0.0)
    weight = 1 / len_half(v)
    total = color * weight[..., None]
    j = rand(x, y, seed) - 0.5
    center = np.stack([x, y], -1) + 0.5
    for i in range(taps):
        t = -1 + 2 * (i + j + 1) / (taps + 1)
        p = np.floor(center + vn * t[..., None]).astype(np.int64)
        py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
        dist = np.hypot(px - x, py - y)
        with np.errstate(invalid="ignore"):
            zx = z + t / 2 * dz
            zy = z[py, px] + t / 2 * dz[py, px]
        zx, zy = np.where(np.isinf(z), z, zx), np.where(np.isinf(z[py, px]), z[py, px], zy)
        f = soft_depth_compare(zx, zy, soft_z)
        b = soft_depth_compare(zy, zx, soft_z)
        vy = v[py, px]
        a = f * cone(dist, vy) + b * cone(dist, v) + cylinder(dist, vy) * cylinder(dist, v) * 2
        weight = weight + a
        total = total + a[..., None] * color[py, px]
    return np.where(moving[..., None], total / weight[..., None], color)


def engine_godot(
    color,
    depth,
    motion,
    camera,
    *,
    quality: str,
    k: int,
    exposure: float,
    soft_z: float,
    seed: int,
    **velocity_params,
) -> np.ndarray:
    """§17.10: (H, W, C) float64 blurred colour: velocity, TileMax → NeighborMax (with the
    direction-keeping dilation) of its half-vectors, then the centred gather."""
    vel = velocity(depth, motion, camera, **velocity_params)
    key = length_key(LENGTH_KEY_STEPS)
    tiles = tile_max(half_velocity(vel[..., :2], exposure, k), k, key)
    neighbor = neighbor_max(tiles, True, key)
    taps = SAMPLES_BY_QUALITY[quality]
    return reconstruct(
        color, vel, neighbor, k=k, exposure=exposure, soft_z=soft_z, taps=taps, seed=seed
    )
