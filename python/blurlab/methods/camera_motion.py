"""The uniforms of the passes that read the camera's motion from a rendered frame's camera
matrices (shaders/common/camera_motion.glsl, docs/spec.md §4 and §17.4): the motion of the
camera alone, and the split of a frame's motion into the camera's part and the rest."""

from __future__ import annotations

import numpy as np


def camera_motion_uniforms(camera: dict) -> dict:
    """The uniforms of common/camera_motion.glsl from a rendered frame's camera matrices."""
    return {
        "view_from_clip": np.linalg.inv(camera["projection"]).astype(np.float32),
        "world_from_view": np.linalg.inv(camera["view"][2]).astype(np.float32),
        "clip_from_world": camera["view_projection"][:2].astype(np.float32),
        "sky_from_clip": camera["sky_from_clip"].astype(np.float32),
        "sky_projection": camera["sky_projection"].astype(np.float32),
        "near": float(camera["near"]),
    }


# What a pass that splits the camera's motion off reads for a frame made from arrays, which has
# no camera: has_camera = False, and the matrices (unread then) that GL still wants set.
_NO_CAMERA = {
    "view_from_clip": np.eye(4, dtype=np.float32),
    "world_from_view": np.eye(4, dtype=np.float32),
    "clip_from_world": np.stack([np.eye(4, dtype=np.float32)] * 2),
    "sky_from_clip": np.eye(4, dtype=np.float32),
    "sky_projection": np.stack([np.eye(4, dtype=np.float32)] * 2),
    "near": 1.0,
    "has_camera": False,
}


def split_camera_uniforms(camera: dict | None) -> dict:
    """The uniforms of a pass that splits the camera's part off a frame's motion
    (common/camera_motion.glsl and `has_camera`), from the frame's camera matrices or None."""
    if camera is None:
        return _NO_CAMERA
    return {**camera_motion_uniforms(camera), "has_camera": True}
