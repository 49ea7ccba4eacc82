"""camera_only, docs/spec.md §4 (Urho3D thesis §2.3.2), in NumPy float64: the box gather along
the motion of the camera alone, both from blurlab.twins.gathers. GPU passes: camera_motion.glsl
and gather.glsl beside it. It reads the camera's transforms, which a frame's arrays do not
hold, so the method declares no twin of the frame's arrays; its test calls this one."""

from __future__ import annotations

import numpy as np

from ...twins.gathers import box_gather, camera_motion


def camera_only(
    color, depth, camera: dict, size, *, taps: int, intensity: float, direction: str, edge: str
) -> np.ndarray:
    """The box gather of `color` along camera_motion(depth, camera, size): what a rendered
    frame with the matrices `camera` (Frame.camera) gives."""
    motion = camera_motion(depth, camera, size)
    return box_gather(color, motion, taps=taps, intensity=intensity, direction=direction, edge=edge)
