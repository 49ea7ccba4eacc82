"""A G-buffer: colour, depth, motion, object ids, and the layers of translucent scenes.

GPU-first (docs/spec.md §1.1): a rendered frame is its textures, and its NumPy arrays are read
from them lazily, once, when a caller asks for one. A frame built from arrays keeps them and
uploads each once, when a pass first needs it (blurlab.methods.passes.frame_textures). What the
CPU needs to choose parameters (depth_range, longest_motion, layer_moves) comes from GPU
reductions that read back a few numbers per 16 x 16 tile, not the image.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from ..io import capture

MOTION_FORMATS = ("rg32f", "rg16f", "rgba8_offset", "rgba8_polar")

# The frame's arrays, each read lazily from the texture named here, or None where it has none
# of its own: (texture, channels taken from it).
ARRAY_SOURCES = {
    "color": ("color", None),
    "depth": ("depth", None),
    "motion": ("motion", None),
    "object_id": ("object_id", None),
    "opaque_color": ("opaque_color", None),
    "translucent": ("translucent", None),
    "translucent_motion": ("translucent_motion", slice(0, 2)),
    "translucent_depth": ("translucent_motion", 2),
}
TWO_SIDED = ("motion_prev", "motion_next")
TRANSLUCENT_LAYER = ("opaque_color", "translucent", "translucent_motion", "translucent_depth")
STATS_TILE = 16  # pixels on a side of a tile of passes/frame_stats.comp
# What a frame keeps of its data once computed, dropped when an array is set.
STATISTICS = (
    "depth_range",
    "moving_speeds",
    "longest_motion",
    "layer_moves",
    "_stats_motion",
    "_stats_translucent_motion",
)


@dataclass
class Frame:
    """docs/spec.md §1 conventions: arrays (H, W, ...), row 0 at the top.

    color      (H, W, 4) linear float32 (or (H, W, 3): alpha 1 is added)
    depth      (H, W) positive linear view distance, +inf where nothing was drawn
    motion     (H, W, 2) pixels from shutter open to close, +x right, +y down
    object_id  (H, W) int32, -1 for the background
    motion_prev, motion_next  (H, W, 2) the two-sided motion of docs/spec.md §17.1: pixels
               from shutter open to the instant, and from the instant to close. Rendered
               frames carry the G-buffer's (textures["motion_sides"]); where both are None
               otherwise, they are derived from motion (as it is when read) as constant
               velocity: f·M and (1 − f)·M, f the instant's place in the shutter.

    opaque_color, translucent, translucent_motion, translucent_depth  scenes with translucent
               surfaces (docs/spec.md §20): then `color` is the composite an engine shows and
               depth, motion and object_id are the opaque layer's; these hold the opaque colour
               (H, W, 4), the translucent layer apart as premultiplied colour Σ and coverage a
               (H, W, 4), and its dominant fragment's motion (H, W, 2) and depth (H, W, +inf
               where none). All four or none (opaque frames).

    A rendered frame holds textures only: each array above is downloaded from its texture the
    first time it is read, and kept (docs/spec.md §1.1). Setting an array replaces the frame's
    data: its other arrays are read first, and its textures and recorded plans are dropped, so
    that the next pass uploads what was set.

    Arrays of any real dtype are converted to float32. Non-finite values are kept as given;
    every method reads them as docs/reliability.md says (NaN color as 0, NaN or non-positive
    depth as far, NaN or infinite motion as none), so they never spread through a blur.
    """

    color: np.ndarray | None = field(default=None, repr=False)
    depth: np.ndarray | None = field(default=None, repr=False)
    motion: np.ndarray | None = field(default=None, repr=False)
    object_id: np.ndarray | None = field(default=None, repr=False)
    shutter: tuple[float, float] = (0.0, 1.0)
    time: float | None = None  # the G-buffer's instant
    motion_format: str = "rg32f"
    camera: dict | None = field(default=None, repr=False)  # matrices at open, close, instant
    timings: dict = field(default_factory=dict)
    # The frame's textures: the truth of a rendered frame, uploaded copies of a frame built
    # from arrays. Rendered ones return to the context's pool when the frame is freed.
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

    @classmethod
    def from_textures(cls, textures: dict, **metadata) -> Frame:
        """A frame whose arrays are the `textures` (by the names of ARRAY_SOURCES, and
        "motion_sides"), read when first asked for: what ctx.render returns. `metadata`:
        shutter, time, motion_format, camera, timings, scene."""
        missing = [name for name in ("color", "depth", "motion") if name not in textures]
        if missing:
            raise ValueError(f"blurlab: Frame.from_textures needs the textures {missing}")
        return cls(textures=dict(textures), **metadata)

    def with_textures(self, textures: dict) -> Frame:
        """A frame of this one's shutter, instant, motion format, camera, scene and object ids
        whose colour, depth and motion are `textures`, read back only if asked for."""
        meta = {key: getattr(self, key) for key in ("shutter", "time", "motion_format", "camera")}
        ids = self.textures.get("object_id")
        if "object_id" not in textures:
            if ids is not None:  # a rendered frame's ids, shared on the GPU
                textures = {**textures, "object_id": ids}
            else:
                meta["object_id"] = self.object_id
        return Frame.from_textures(textures, scene=self.scene, **meta)

    def __post_init__(self):
        stored = self.__dict__
        if stored.get("_color") is None and "color" not in self.textures:
            raise TypeError(
                "blurlab: a Frame needs color, depth and motion arrays "
                "(Frame(color, depth, motion)), or the textures of a rendered frame"
            )
        for name in ("depth", "motion"):
            if stored.get(f"_{name}") is None and name not in self.textures:
                raise TypeError(f"blurlab: a Frame needs {name} as well as color")
        if stored.get("_color") is not None:
            color = _float_image(stored["_color"], "color", (3, 4))
            if color.shape[2] == 3:
                alpha = np.ones(color.shape[:2] + (1,), np.float32)
                color = np.concatenate([color, alpha], axis=2)
            stored["_color"] = color
        h, w = self.shape
        if stored.get("_depth") is not None:
            depth = stored["_depth"]
            if isinstance(depth, np.ndarray) and depth.ndim == 2:
                depth = depth[..., None]
            depth = _float_image(depth, "depth", (1,))[..., 0]
            if depth.shape != (h, w):
                raise ValueError(f"blurlab: depth has shape {depth.shape}, color is {(h, w)}")
            stored["_depth"] = depth
        if stored.get("_motion") is not None:
            motion = _float_image(stored["_motion"], "motion", (2,))
            if motion.shape[:2] != (h, w):
                raise ValueError(f"blurlab: motion has shape {motion.shape}, color is {(h, w)}")
            stored["_motion"] = motion
        if stored.get("_object_id") is not None:
            stored["_object_id"] = _object_ids(stored["_object_id"], (h, w))
        elif "object_id" not in self.textures and stored.get("_depth") is not None:
            stored["_object_id"] = _drawn_ids(stored["_depth"])
        if not isinstance(self.motion_format, str) or self.motion_format not in MOTION_FORMATS:
            raise ValueError(f"blurlab: motion_format must be one of {MOTION_FORMATS}")
        self._two_sided_motion()
        self._translucent_layer()
        stored["_built"] = True

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W), known without reading an array."""
        color = self.__dict__.get("_color")
        if color is not None:
            return color.shape[:2]
        texture = self.textures["color"]
        return texture.height, texture.width

    @property
    def size(self) -> tuple[int, int]:
        """(W, H)."""
        height, width = self.shape
        return width, height

    @property
    def sides_derived(self) -> bool:
        """Whether motion_prev and motion_next are derived from motion (§17.1): the frame has
        neither the G-buffer's halves nor given ones."""
        return "motion_sides" not in self.textures and self.__dict__.get("_motion_prev") is None

    @property
    def on_host(self) -> tuple[str, ...]:
        """The names of the arrays that are on the host now (given, or already read)."""
        return tuple(n for n in ARRAY_SOURCES if self.__dict__.get(f"_{n}") is not None)

    def _translucent_layer(self):
        """docs/spec.md §20: checks the translucent layer's arrays (all four or none)."""
        given = [self.__dict__.get(f"_{name}") is not None for name in TRANSLUCENT_LAYER]
        if not any(given):
            return
        if not all(given):
            raise ValueError(f"blurlab: give all of {TRANSLUCENT_LAYER}, or none")
        h, w = self.shape
        for name, channels in zip(TRANSLUCENT_LAYER, (4, 4, 2, 1), strict=True):
            value = self.__dict__[f"_{name}"]
            if name == "translucent_depth" and isinstance(value, np.ndarray) and value.ndim == 2:
                value = value[..., None]
            value = _float_image(value, name, (channels,))
            if value.shape[:2] != (h, w):
                raise ValueError(f"blurlab: {name} has shape {value.shape}, color is {(h, w)}")
            self.__dict__[f"_{name}"] = value[..., 0] if channels == 1 else value

    @property
    def layered(self) -> bool:
        """Whether the frame carries a translucent layer (docs/spec.md §20)."""
        return self.__dict__.get("_translucent") is not None or "translucent" in self.textures

    def _two_sided_motion(self):
        """docs/spec.md §17.1: checks the given halves (both or neither)."""
        given = [self.__dict__.get(f"_{name}") for name in TWO_SIDED]
        missing = [half is None for half in given]
        if all(missing):
            return
        if any(missing):
            raise ValueError("blurlab: give both motion_prev and motion_next, or neither")
        motion_shape = self.shape + (2,)
        for name, half in zip(TWO_SIDED, given, strict=True):
            half = _float_image(half, name, (2,))
            if half.shape != motion_shape:
                raise ValueError(
                    f"blurlab: {name} has shape {half.shape}, motion is {motion_shape}"
                )
            self.__dict__[f"_{name}"] = half

    def _derived_half(self, name: str) -> np.ndarray:
        """Constant velocity around the instant (§17.1): f·M before it, (1 − f)·M after it,
        from the frame's motion as it is now."""
        f = self.instant_fraction
        share = f if name == "motion_prev" else 1.0 - f
        with np.errstate(invalid="ignore", over="ignore"):  # inf · 0 in non-finite input
            return (self.motion * np.float32(share)).astype(np.float32)

    def _read(self, name: str):
        """The array `name` from its texture (ARRAY_SOURCES), kept; None where there is none."""
        key, channels = ARRAY_SOURCES[name]
        texture = self.textures.get(key)
        if texture is None:
            if name == "object_id":  # no ids of its own: drawn pixels are object 0
                ids = _drawn_ids(self.depth)
                self.__dict__["_object_id"] = ids
                return ids
            return None
        array = texture.download()
        if key == "translucent_motion":  # one texture holds the layer's motion and depth
            self.__dict__["_translucent_motion"] = np.ascontiguousarray(array[..., :2])
            self.__dict__["_translucent_depth"] = np.ascontiguousarray(array[..., 2])
            return self.__dict__[f"_{name}"]
        if name == "object_id":
            array = _object_ids(array, self.shape)
        self.__dict__[f"_{name}"] = array
        return array

    def _replace_data(self) -> None:
        """Before an array is set on a built frame: reads every array it does not hold yet,
        then drops its textures, plans and statistics, which described the old data."""
        for name, (key, _) in ARRAY_SOURCES.items():
            if self.__dict__.get(f"_{name}") is None and key in self.textures:
                self._read(name)
        if self.__dict__.get("_motion_prev") is None and "motion_sides" in self.textures:
            self.motion_prev  # noqa: B018 (reads both halves)
        self.textures = {}
        self.plans.clear()
        for cached in STATISTICS:
            self.__dict__.pop(cached, None)

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
        ``camera_motion`` as `blurlab.io.capture.read_exr` takes them."""
        return cls(**capture.read_exr(path, **kwargs))

    def _stats(self, motion_key: str = "motion") -> dict | None:
        """The GPU statistics of the frame's depth and motion textures (passes/frame_stats.comp)
        where the arrays are not on the host, reduced once per frame and motion texture; None
        where they are (NumPy reads them then)."""
        stored_name = "_motion" if motion_key == "motion" else "_translucent_motion"
        if self.__dict__.get(stored_name) is not None or motion_key not in self.textures:
            return None
        if motion_key == "motion" and (
            self.__dict__.get("_depth") is not None or "depth" not in self.textures
        ):
            return None
        cached = f"_stats_{motion_key}"
        if cached not in self.__dict__:
            depth = self.textures.get("depth", self.textures[motion_key])
            self.__dict__[cached] = frame_stats(depth, self.textures[motion_key])
        return self.__dict__[cached]

    @functools.cached_property
    def depth_range(self) -> tuple[float, float] | None:
        """(nearest, farthest) finite positive depth, or None if nothing was drawn. Computed
        once, on the GPU for a rendered frame whose depth was not read. Non-positive and NaN
        depths are far (docs/reliability.md), so they do not count."""
        stats = self._stats()
        if stats is not None:
            return stats["depth_range"]
        finite = self.depth[np.isfinite(self.depth) & (self.depth > 0)]
        return (float(finite.min()), float(finite.max())) if finite.size else None

    @functools.cached_property
    def longest_motion(self) -> float:
        """The longest finite motion in pixels (0 where none): what the reference's number of
        sub-frames follows (docs/spec.md §1). On the GPU for a rendered frame."""
        stats = self._stats()
        if stats is not None:
            return stats["longest_motion"]
        speed = np.hypot(self.motion[..., 0], self.motion[..., 1])
        speed = speed[np.isfinite(speed)]
        return float(speed.max()) if speed.size else 0.0

    @functools.cached_property
    def layer_moves(self) -> float:
        """The largest |component| of the translucent layer's motion (inf where any is not
        finite, 0 without a layer): how much any of its fragments moves."""
        stats = self._stats("translucent_motion")
        if stats is not None:
            return stats["largest_component"]
        motion = self.translucent_motion
        if motion is None or motion.size == 0:
            return 0.0
        largest = float(np.abs(motion).max())
        return largest if not math.isnan(largest) else math.inf

    @functools.cached_property
    def moving_speeds(self) -> np.ndarray:
        """moving_speeds(self.motion): what the "auto" parameter rules read. Computed once per
        frame (it reads the motion array)."""
        return moving_speeds(self.motion)


def moving_speeds(motion: np.ndarray) -> np.ndarray:
    """|M| in pixels of the pixels that move at least 1 px over the shutter (finite motion
    only), sorted."""
    speed = np.linalg.norm(motion, axis=-1)
    return np.sort(speed[np.isfinite(speed) & (speed >= 1.0)])


def frame_stats(depth, motion) -> dict:
    """Statistics of a depth and a motion texture of one context, reduced on the GPU per 16 x 16
    tile (passes/frame_stats.comp) and finished here over the tiles: depth_range (finite
    positive depth, or None), longest_motion (np.hypot of the longest finite motion, chosen per
    tile by the shader) and largest_component (max |motion component|, inf where any is not
    finite). Reads back 20 bytes per tile."""
    ctx = depth.context
    height, width = depth.height, depth.width
    tiles = (-(-height // STATS_TILE), -(-width // STATS_TILE))
    tile_stats, tile_extent = ctx.pooled(tiles + (4,)), ctx.pooled(tiles)
    try:
        ctx.shader_pass("passes/frame_stats.comp").run(
            {"depth": depth, "motion": motion},
            {"tile_stats": tile_stats, "tile_extent": tile_extent},
        )
        stats, extent = tile_stats.download(), tile_extent.download()
    finally:
        ctx.recycle(tile_stats, tile_extent)
    near, far = float(stats[..., 0].min()), float(stats[..., 1].max())
    speeds = np.hypot(stats[..., 2], stats[..., 3])
    speeds[~np.isfinite(speeds)] = 0.0  # beyond float32's range, as the NumPy path drops them
    return {
        "depth_range": (near, far) if near <= far else None,
        "longest_motion": float(speeds.max()),
        "largest_component": float(extent.max()),
    }


def _object_ids(ids, shape) -> np.ndarray:
    ids = np.asarray(ids)
    if ids.dtype.kind not in "fiu":
        raise TypeError(f"blurlab: frame object_id has dtype {ids.dtype}; expected integers")
    with np.errstate(invalid="ignore"):
        ids = ids.astype(np.int32)
    if ids.shape != tuple(shape):
        raise ValueError(f"blurlab: object_id has shape {ids.shape}, expected {tuple(shape)}")
    return ids


def _drawn_ids(depth: np.ndarray) -> np.ndarray:
    """Object 0 where something was drawn (finite positive depth), -1 elsewhere."""
    drawn = np.isfinite(depth) & (depth > 0)
    return np.where(drawn, 0, -1).astype(np.int32)


def _set_array(name: str):
    """The setter of frame.NAME: on a built frame, the new array replaces the frame's data."""

    def set_(self, value) -> None:
        if self.__dict__.get("_built"):
            self._replace_data()
        self.__dict__[f"_{name}"] = value

    return set_


def _array_property(name: str) -> property:
    """frame.NAME: the array given or already read, else read from its texture now."""

    def get(self):
        value = self.__dict__.get(f"_{name}")
        return value if value is not None else self._read(name)

    doc = f"The frame's {name} array (read from the GPU when first asked)"
    return property(get, _set_array(name), doc=doc)


def _two_sided_property(name: str) -> property:
    """frame.motion_prev / motion_next: the given half, the G-buffer's (downloaded from
    textures["motion_sides"] when first read), or the one derived from motion now."""

    def get(self) -> np.ndarray:
        given = self.__dict__.get(f"_{name}")
        if given is None and self.textures.get("motion_sides") is not None:
            sides = self.textures["motion_sides"].download()
            self.__dict__["_motion_prev"] = np.ascontiguousarray(sides[..., :2])
            self.__dict__["_motion_next"] = np.ascontiguousarray(sides[..., 2:])
            given = self.__dict__[f"_{name}"]
        return given if given is not None else self._derived_half(name)

    return property(get, _set_array(name), doc=f"(H, W, 2) {name} of docs/spec.md §17.1")


# The dataclass's __init__ assigns these through the properties, which keep the arrays (and
# read rendered ones from the GPU on first use).
for _name in ARRAY_SOURCES:
    setattr(Frame, _name, _array_property(_name))
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
