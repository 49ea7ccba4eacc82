"""A shutter from an engine's frame timing (docs/spec.md §15.2): a frame rate, a shutter angle
and a frame number give the interval (t0, t1) in scene seconds that every render, reference and
method takes. Scene time is the glTF file's time, which Blender's exporter writes as
frame / fps."""

from __future__ import annotations

import math
from numbers import Real

POSITIONS = ("center", "start", "end")  # Blender's Center, Start and End on Frame
MAX_ANGLE = 360.0  # a shutter open longer than the frame is not what an engine offers


def _number(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ValueError(f"blurlab: shutter {what} must be a finite number, not {value!r}")
    return float(value)


def shutter(
    fps: float = 60.0, angle: float = 180.0, frame: float = 0.0, position: str = "center"
) -> tuple[float, float]:
    """The shutter (t0, t1), in seconds, of frame `frame` at `fps` frames per second with a
    shutter of `angle` degrees, in [0, 360] (360 = the whole frame interval; Blender's
    "Shutter" in frames is angle / 360). The frame is shown at t = frame / fps, the time glTF
    files exported by Blender give it; `position` "center" (the default, as engines and
    Blender's default do) centres the shutter on that time, "start" opens it there (Blender's
    "Start on Frame") and "end" closes it there (docs/spec.md §15.2)."""
    fps, angle, frame = (
        _number(
            fps,
            "fps",
        ),
        _number(angle, "angle"),
        _number(frame, "frame"),
    )
    if fps <= 0:
        raise ValueError(f"blurlab: shutter fps must be > 0, not {fps}")
    if not 0.0 <= angle <= MAX_ANGLE:
        raise ValueError(
            f"blurlab: shutter angle must be in [0, {MAX_ANGLE:g}] degrees, not {angle}"
        )
    if position not in POSITIONS:
        raise ValueError(f"blurlab: shutter position must be one of {POSITIONS}, not {position!r}")
    at, length = frame / fps, angle / MAX_ANGLE / fps
    opens = {"center": at - length / 2, "start": at, "end": at - length}[position]
    return opens, opens + length
