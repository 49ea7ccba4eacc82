"""Per-object and camera motion-blur scales (docs/spec.md §12.1): an object whose
``motion_blur`` is s is placed at t_c + s·(t − t_c) whenever the scene is evaluated at t, with
t_c the centre of the shutter being blurred; ``Scene.camera_motion_blur`` does the same for the
camera. s = 1 is the motion as given, s = 0 the sharp instant t_c.

``scaled_scene`` applies the scales once, to a copy of the scene whose motions carry them, so
that every G-buffer, sub-frame and reference drawn from that copy (and from the Frame that
holds it) pivots on the same t_c."""

from __future__ import annotations

import dataclasses
import math
from numbers import Real

import numpy as np

from .motion import Motion


def check_blur_scale(value, what: str) -> float:
    """`value` as a motion-blur scale: a number in [0, 1]."""
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ValueError(f"blurlab: {what} must be a number in [0, 1], not {value!r}")
    if not 0.0 <= value <= 1.0:
        raise ValueError(
            f"blurlab: {what} must be in [0, 1] (0 renders sharp, 1 blurs fully), not {value}"
        )
    return float(value)


def blur_time(scale: float, t: float, centre: float) -> float:
    """The time an object with blur scale `scale` is evaluated at when the scene is at t."""
    return centre + scale * (t - centre)


class TimeScaledMotion(Motion):
    """`motion` evaluated at blur_time(scale, t, centre)."""

    def __init__(self, motion: Motion, scale: float, centre: float):
        self.motion, self.scale, self.centre = motion, scale, centre

    def transform(self, t: float) -> np.ndarray:
        return self.motion.transform(blur_time(self.scale, t, self.centre))


class CameraHeld(Motion):
    """The motion of an object the camera carries (a first-person weapon, a cockpit): the
    camera's world transform at t times `local` (the object's pose in camera space, a Motion,
    or None for a fixed pose). `camera` is the scene's camera. Its blur scale applies to `local`
    alone; the camera's part follows the camera's own scale (docs/spec.md §12.1)."""

    def __init__(self, camera, local: Motion | None = None):
        self.camera, self.local = camera, local

    def transform(self, t: float) -> np.ndarray:
        local = np.eye(4) if self.local is None else self.local.transform(t)
        return self.camera.world(t) @ local


class TimeScaledSkeleton:
    """A skeleton (bl.Skeleton or a glTF skin) posed at blur_time(scale, t, centre)."""

    def __init__(self, skeleton, scale: float, centre: float):
        self.skeleton, self.scale, self.centre = skeleton, scale, centre

    @property
    def bones(self):
        return self.skeleton.bones

    def matrices(self, t: float) -> np.ndarray:
        return self.skeleton.matrices(blur_time(self.scale, t, self.centre))


def scaled_scene(scene, shutter: tuple[float, float]):
    """The bl.Scene `scene` (not imported here: model.py imports this module) with its blur
    scales applied around the centre of `shutter`: the scene itself when every scale is 1
    (nothing changes, not a bit), else a copy whose objects and camera move on scaled time and
    whose scales are 1 (so applying it again changes nothing)."""
    camera_scale = check_blur_scale(scene.camera_motion_blur, "camera_motion_blur")
    scales = [
        check_blur_scale(obj.motion_blur, f"motion_blur of {obj.name}") for obj in scene.objects
    ]
    if camera_scale == 1.0 and all(s == 1.0 for s in scales):
        return scene
    centre = 0.5 * (shutter[0] + shutter[1])
    camera = scene.camera
    if camera_scale != 1.0 and camera.motion is not None:
        camera = dataclasses.replace(
            camera, motion=TimeScaledMotion(camera.motion, camera_scale, centre)
        )
    objects = []
    for obj, s in zip(scene.objects, scales, strict=True):
        motion, skeleton = obj.motion, obj.skeleton
        if isinstance(motion, CameraHeld) and motion.camera is scene.camera:
            local = motion.local  # scaled in camera space; the camera carries it as it moves
            if local is not None and s != 1.0:
                local = TimeScaledMotion(local, s, centre)
            motion = CameraHeld(camera, local)
        elif motion is not None and s != 1.0:
            motion = TimeScaledMotion(motion, s, centre)
        if skeleton is not None and s != 1.0:
            skeleton = TimeScaledSkeleton(skeleton, s, centre)
        objects.append(dataclasses.replace(obj, motion=motion, skeleton=skeleton, motion_blur=1.0))
    return dataclasses.replace(scene, objects=objects, camera=camera, camera_motion_blur=1.0)
