"""Motion over the shutter: transforms as functions of time, evaluated, never integrated.

A ``Motion`` gives a 4x4 float64 world transform at any time t (seconds). Quaternions are
(w, x, y, z). Angles are radians; spin rates radians per second.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


def quaternion(axis, angle: float) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a rotation by `angle` about `axis`."""
    axis = np.asarray(axis, dtype=np.float64)
    norm = np.linalg.norm(axis)
    if not np.isfinite(norm) or norm == 0 or not math.isfinite(angle):
        raise ValueError(f"blurlab: rotation axis {axis} / angle {angle} must be finite, axis != 0")
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis / norm])


def quaternion_matrix(q) -> np.ndarray:
    q = np.asarray(q, dtype=np.float64)
    # np.linalg.norm's own arithmetic (sqrt of the dot product), then Python floats: the same
    # IEEE operations as NumPy scalars at a fraction of the cost (a reference renders
    # thousands of sub-frames, each composing every object's transform three times).
    w, x, y, z = (q / math.sqrt(q.dot(q))).tolist()
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def slerp(q0, q1, s: float) -> np.ndarray:
    """Spherical linear interpolation along the shorter arc."""
    q0, q1 = np.asarray(q0, float), np.asarray(q1, float)
    d = float(np.dot(q0, q1))
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:  # nearly parallel: linear interpolation is exact to float precision
        q = q0 + s * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = math.acos(d)
    return (math.sin((1 - s) * theta) * q0 + math.sin(s * theta) * q1) / math.sin(theta)


def compose(position=(0, 0, 0), rotation=(1, 0, 0, 0), scale=1.0) -> np.ndarray:
    """T · R · S as a 4x4 matrix."""
    m = np.zeros((4, 4))
    m[:3, :3] = quaternion_matrix(rotation) * np.asarray(scale, float)  # a scalar or per axis
    m[:3, 3] = position
    m[3, 3] = 1.0
    return m


def _vector(value, what: str, size: int = 3) -> np.ndarray:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (size,) or not np.isfinite(v).all():
        raise ValueError(f"blurlab: {what} must be {size} finite numbers, not {value!r}")
    return v


class Motion:
    """A world transform as a function of time."""

    def transform(self, t: float) -> np.ndarray:
        raise NotImplementedError

    @staticmethod
    def static(position=(0, 0, 0), rotation=(1, 0, 0, 0), scale=1.0) -> Motion:
        return Linear(position, (0, 0, 0), rotation=rotation, scale=scale)

    @staticmethod
    def linear(
        start=(0, 0, 0),
        velocity=(0, 0, 0),
        spin_axis=None,
        spin_rate: float = 0.0,
        rotation=(1, 0, 0, 0),
        scale=1.0,
    ) -> Motion:
        """Position start + velocity·t; spin about `spin_axis` (through the object's origin) at
        `spin_rate` rad/s on top of the fixed `rotation`."""
        return Linear(start, velocity, spin_axis, spin_rate, rotation, scale)

    @staticmethod
    def keyframes(frames: Sequence[Keyframe]) -> Motion:
        """Position and scale interpolated linearly, rotation by slerp; held outside the keys."""
        return Keyframes(list(frames))


@dataclass
class Linear(Motion):
    start: Sequence[float] = (0, 0, 0)
    velocity: Sequence[float] = (0, 0, 0)
    spin_axis: Sequence[float] | None = None
    spin_rate: float = 0.0
    rotation: Sequence[float] = (1, 0, 0, 0)
    scale: float | Sequence[float] = 1.0

    def __post_init__(self):
        self.start = _vector(self.start, "start")
        self.velocity = _vector(self.velocity, "velocity")
        self.rotation = _vector(self.rotation, "rotation", 4)
        if not math.isfinite(self.spin_rate):
            raise ValueError(f"blurlab: spin_rate must be finite, not {self.spin_rate}")
        if self.spin_axis is not None:
            quaternion(self.spin_axis, 0.0)  # validates the axis
        scale = np.asarray(self.scale, dtype=np.float64)
        if not np.isfinite(scale).all() or np.any(scale == 0):
            raise ValueError(f"blurlab: scale must be finite and non-zero, not {self.scale!r}")

    def transform(self, t: float) -> np.ndarray:
        rotation = self.rotation
        if self.spin_axis is not None and self.spin_rate != 0.0:
            spin = quaternion(self.spin_axis, self.spin_rate * t)
            rotation = _multiply(spin, rotation)
        return compose(self.start + self.velocity * t, rotation, self.scale)


@dataclass
class Keyframe:
    time: float
    position: Sequence[float] = (0, 0, 0)
    rotation: Sequence[float] = (1, 0, 0, 0)
    scale: float | Sequence[float] = 1.0


@dataclass
class Keyframes(Motion):
    frames: list[Keyframe] = field(default_factory=list)

    def __post_init__(self):
        if not self.frames:
            raise ValueError("blurlab: Motion.keyframes needs at least one keyframe")
        times = [k.time for k in self.frames]
        if not all(math.isfinite(t) for t in times) or any(
            b <= a for a, b in zip(times, times[1:], strict=False)
        ):
            raise ValueError(f"blurlab: keyframe times must be finite and increasing: {times}")
        for k in self.frames:
            _vector(k.position, "keyframe position")
            _vector(k.rotation, "keyframe rotation", 4)

    def transform(self, t: float) -> np.ndarray:
        frames = self.frames
        if t <= frames[0].time or len(frames) == 1:
            k = frames[0]
            return compose(k.position, k.rotation, k.scale)
        if t >= frames[-1].time:
            k = frames[-1]
            return compose(k.position, k.rotation, k.scale)
        i = max(j for j, k in enumerate(frames) if k.time <= t)
        a, b = frames[i], frames[i + 1]
        s = (t - a.time) / (b.time - a.time)
        lerp = lambda x, y: (1 - s) * np.asarray(x, float) + s * np.asarray(y, float)  # noqa: E731
        return compose(
            lerp(a.position, b.position), slerp(a.rotation, b.rotation, s), lerp(a.scale, b.scale)
        )


def _multiply(a, b) -> np.ndarray:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


@dataclass
class Bone:
    """One bone: its parent's index (-1 for a root), its rest transform relative to the parent,
    and its motion relative to the parent (None: stays at rest)."""

    parent: int
    rest: np.ndarray
    motion: Motion | None = None


@dataclass
class Skeleton:
    """Bones in parent-before-child order. The skinning matrix of bone i at time t is
    global_i(t) · inverse(global_i(rest)), applied to rest-pose vertices (ogldev tutorial 41's
    approach: the same bones evaluated at t0 and t1 give the motion)."""

    bones: list[Bone]

    def __post_init__(self):
        for i, bone in enumerate(self.bones):
            if not -1 <= bone.parent < i:
                raise ValueError(f"blurlab: bone {i}'s parent {bone.parent} must come before it")
            bone.rest = np.asarray(bone.rest, dtype=np.float64)
            if bone.rest.shape != (4, 4) or not np.isfinite(bone.rest).all():
                raise ValueError(f"blurlab: bone {i}'s rest transform must be a finite 4x4")

    def _globals(self, local) -> list[np.ndarray]:
        out: list[np.ndarray] = []
        for i, bone in enumerate(self.bones):
            m = local(i, bone)
            out.append(m if bone.parent < 0 else out[bone.parent] @ m)
        return out

    def matrices(self, t: float) -> np.ndarray:
        """(bones, 4, 4) skinning matrices at time t."""
        rest = self._globals(lambda i, b: b.rest)
        posed = self._globals(
            lambda i, b: b.rest @ (b.motion.transform(t) if b.motion else np.eye(4))
        )
        return np.stack([p @ np.linalg.inv(r) for p, r in zip(posed, rest, strict=True)])
