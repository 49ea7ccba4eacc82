"""A rendered (or user-supplied) G-buffer: color, depth, motion, object ids, as NumPy arrays."""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from . import capture

MOTION_FORMATS = ("rg32f", "rg16f", "rgba8_offset", "rgba8_polar")


@dataclass
class Frame:
    """docs/spec.md §1 conventions: arrays (H, W, ...), row 0 at the top.

    color      (H, W, 4) linear float32 (or (H, W, 3): alpha 1 is added)
    depth      (H, W) positive linear view distance, +inf where nothing was drawn
    motion     (H, W, 2) pixels from shutter open to close, +x right, +y down
    object_id  (H, W) int32, -1 for the background
    motion_prev, motion_next  (H, W, 2) the two-sided motion of docs/spec.md §17.1: pixels
               from shutter open to the instant, and from the instant to close. Rendered
               frames carry the G-buffer's (downloaded from textures["motion_sides"] when first
               read); where both are None otherwise, they are derived from motion
               (as it is when read) as constant velocity: f·M and (1 − f)·M, f the instant's
               place in the shutter.

    opaque_color, translucent, translucent_motion, translucent_depth  scenes with translucent
               surfaces (docs/spec.md §20): then `color` is the composite an engine shows and
               depth, motion and object_id are the opaque layer's; these hold the opaque colour
               (H, W, 4), the translucent layer apart as premultiplied colour Σ and coverage a
               (H, W, 4), and its dominant fragment's motion (H, W, 2) and depth (H, W, +inf
               where none). All four or none (opaque frames).

    Arrays of any real dtype are converted to float32. Non-finite values are kept as given;
    every method reads them as docs/reliability.md says (NaN color as 0, NaN or non-positive
    depth as far, NaN or infinite motion as none), so they never spread through a blur.
    """

    color: np.ndarray
    depth: np.ndarray
    motion: np.ndarray
    object_id: np.ndarray | None = None
    shutter: tuple[float, float] = (0.0, 1.0)
    time: float | None = None  # the G-buffer's instant
    motion_format: str = "rg32f"
    camera: dict | None = None  # matrices at open, close and the instant (rendered frames)
    timings: dict = field(default_factory=dict)
    # GPU copies where rendered; they return to the context's pool when the frame is freed.
    textures: dict = field(default_factory=dict, repr=False)
    scene: object = field(default=None, repr=False)  # the Scene a rendered frame came from
    motion_prev: np.ndarray | None = field(default=None, repr=False)
    motion_next: np.ndarray | None = field(default=None, repr=False)
    opaque_color: np.ndarray | None = field(default=None, repr=False)
    translucent: np.ndarray | None = field(default=None, repr=False)
    translucent_motion: np.ndarray | None = field(default=None, repr=False)
    translucent_depth: np.ndarray | None = field(default=None, repr=False)
    # Recorded dispatch plans of the methods run on this frame (blurlab.methods.plans), by
    # method, backend and given parameters: set by blur, never by a constructor or a copy.
    plans: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        self.color = _float_image(self.color, "color", (3, 4))
        h, w = self.color.shape[:2]
        if self.color.shape[2] == 3:
            self.color = np.concatenate([self.color, np.ones((h, w, 1), np.float32)], axis=2)
        if isinstance(self.depth, np.ndarray) and self.depth.ndim == 2:
            self.depth = self.depth[..., None]
        self.depth = _float_image(self.depth, "depth", (1,))[..., 0]
        if self.depth.shape != (h, w):
            raise ValueError(f"blurlab: depth has shape {self.depth.shape}, color is {(h, w)}")
        self.motion = _float_image(self.motion, "motion", (2,))
        if self.motion.shape[:2] != (h, w):
            raise ValueError(f"blurlab: motion has shape {self.motion.shape}, color is {(h, w)}")
        if self.object_id is None:
            drawn = np.isfinite(self.depth) & (self.depth > 0)
            self.object_id = np.where(drawn, 0, -1).astype(np.int32)
        self.object_id = np.asarray(self.object_id)
        if self.object_id.dtype.kind not in "fiu":
            raise TypeError(
                f"blurlab: frame object_id has dtype {self.object_id.dtype}; expected integers"
            )
        with np.errstate(invalid="ignore"):
            self.object_id = self.object_id.astype(np.int32)
        if self.object_id.shape != (h, w):
            raise ValueError(
                f"blurlab: object_id has shape {self.object_id.shape}, expected {(h, w)}"
            )
        if not isinstance(self.motion_format, str) or self.motion_format not in MOTION_FORMATS:
            raise ValueError(f"blurlab: motion_format must be one of {MOTION_FORMATS}")
        self._two_sided_motion()
        self._translucent_layer()

    def _translucent_layer(self):
        """docs/spec.md §20: checks the translucent layer's arrays (all four or none)."""
        given = [getattr(self, name) is not None for name in TRANSLUCENT_LAYER]
        if not any(given):
            return
        if not all(given):
            raise ValueError(f"blurlab: give all of {TRANSLUCENT_LAYER}, or none")
        h, w = self.color.shape[:2]
        for name, channels in zip(TRANSLUCENT_LAYER, (4, 4, 2, 1), strict=True):
            value = getattr(self, name)
            if name == "translucent_depth" and isinstance(value, np.ndarray) and value.ndim == 2:
                value = value[..., None]
            value = _float_image(value, name, (channels,))
            if value.shape[:2] != (h, w):
                raise ValueError(f"blurlab: {name} has shape {value.shape}, color is {(h, w)}")
            setattr(self, name, value[..., 0] if channels == 1 else value)

    @property
    def layered(self) -> bool:
        """Whether the frame carries a translucent layer (docs/spec.md §20)."""
        return self.translucent is not None

    def _two_sided_motion(self):
        """docs/spec.md §17.1: checks the given halves (both or neither)."""
        given = [self.__dict__.get(f"_{name}") for name in TWO_SIDED]
        missing = [half is None for half in given]
        if all(missing):
            return
        if any(missing):
            raise ValueError("blurlab: give both motion_prev and motion_next, or neither")
        for name, half in zip(TWO_SIDED, given, strict=True):
            half = _float_image(half, name, (2,))
            if half.shape != self.motion.shape:
                raise ValueError(
                    f"blurlab: {name} has shape {half.shape}, motion is {self.motion.shape}"
                )
            self.__dict__[f"_{name}"] = half

    def _derived_half(self, name: str) -> np.ndarray:
        """Constant velocity around the instant (§17.1): f·M before it, (1 − f)·M after it,
        from the frame's motion as it is now."""
        f = self.instant_fraction
        share = f if name == "motion_prev" else 1.0 - f
        with np.errstate(invalid="ignore", over="ignore"):  # inf · 0 in non-finite input
            return (self.motion * np.float32(share)).astype(np.float32)

    @property
    def instant_fraction(self) -> float:
        """Where the instant lies in the shutter, 0 (open) to 1 (close); 0.5 where the frame
        has no instant or the shutter has no length."""
        t0, t1 = self.shutter
        if self.time is None or not t1 > t0:
            return 0.5
        return min(max((self.time - t0) / (t1 - t0), 0.0), 1.0)

    @classmethod
    def from_exr(cls, path=None, **kwargs) -> Frame:
        """A frame captured by another renderer, from EXR files (docs/spec.md §16): one
        multi-layer file, or ``color=``, ``depth=``, ``motion=`` paths; ``convention``
        (blurlab, blender, unreal, unity, uv, ndc), ``shutter_fraction``, ``depth_encoding``,
        ``near``, ``far``, ``reversed_z``, ``shutter``, ``velocity_encoding`` and
        ``camera_motion`` as `blurlab.capture.read_exr` takes them."""
        return cls(**capture.read_exr(path, **kwargs))

    @functools.cached_property
    def depth_range(self) -> tuple[float, float] | None:
        """(nearest, farthest) finite positive depth, or None if nothing was drawn. Computed
        once: at 1080p it costs milliseconds, and default parameters ask for it on every blur.
        Non-positive and NaN depths are far (docs/reliability.md), so they do not count."""
        finite = self.depth[np.isfinite(self.depth) & (self.depth > 0)]
        return (float(finite.min()), float(finite.max())) if finite.size else None

    @functools.cached_property
    def moving_speeds(self) -> np.ndarray:
        """moving_speeds(self.motion): what the "auto" parameter rules read. Computed once per
        frame."""
        return moving_speeds(self.motion)

    @property
    def size(self) -> tuple[int, int]:
        """(W, H)."""
        return self.color.shape[1], self.color.shape[0]


def moving_speeds(motion: np.ndarray) -> np.ndarray:
    """|M| in pixels of the pixels that move at least 1 px over the shutter (finite motion
    only), sorted."""
    speed = np.linalg.norm(motion, axis=-1)
    return np.sort(speed[np.isfinite(speed) & (speed >= 1.0)])


TWO_SIDED = ("motion_prev", "motion_next")
TRANSLUCENT_LAYER = ("opaque_color", "translucent", "translucent_motion", "translucent_depth")


def _two_sided_property(name: str) -> property:
    """frame.motion_prev / motion_next: the given half, or the one derived from motion now."""

    def get(self) -> np.ndarray:
        given = self.__dict__.get(f"_{name}")
        if given is None and self.textures.get("motion_sides") is not None:
            # A rendered frame: the G-buffer's halves, downloaded on first use only.
            sides = self.textures["motion_sides"].download()
            self.__dict__["_motion_prev"] = np.ascontiguousarray(sides[..., :2])
            self.__dict__["_motion_next"] = np.ascontiguousarray(sides[..., 2:])
            given = self.__dict__[f"_{name}"]
        return given if given is not None else self._derived_half(name)

    def set_(self, value) -> None:
        self.__dict__[f"_{name}"] = value

    return property(get, set_, doc=f"(H, W, 2) {name} of docs/spec.md §17.1")


# The dataclass's __init__ takes them as arguments; the properties then keep the derived
# halves in step with `motion` when no half was given.
for _name in TWO_SIDED:
    setattr(Frame, _name, _two_sided_property(_name))


def _float_image(array, what: str, channels: tuple[int, ...]) -> np.ndarray:
    if not isinstance(array, np.ndarray):
        raise TypeError(
            f"blurlab: frame {what} must be a numpy.ndarray, not {type(array).__name__}"
        )
    if array.ndim != 3 or array.shape[2] not in channels or array.size == 0:
        raise ValueError(
            f"blurlab: frame {what} has shape {array.shape}; expected "
            + ("(H, W)" if channels == (1,) else f"(H, W, C), C in {channels}")
        )
    if array.dtype.kind not in "fiu":
        raise TypeError(f"blurlab: frame {what} has dtype {array.dtype}; expected a float type")
    with np.errstate(over="ignore"):  # float64 beyond float32's range becomes +-inf
        return np.ascontiguousarray(array, dtype=np.float32)
