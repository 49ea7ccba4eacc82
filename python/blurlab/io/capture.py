"""G-buffers captured by other renderers, read from EXR files for `bl.Frame.from_exr`
(docs/spec.md §16): colour, depth and motion, each from its own file or from the layers of one
multi-layer file, with the motion and depth conventions of the renderer that wrote them.

Every convention converts to blurlab's: M in pixels from shutter open to close, +x right,
+y down (§1), scaled by `shutter_fraction` where the stored motion spans a whole frame.

A captured sequence is a file pattern, `shot.####.exr` (`sequence`, §16.6): its frames are
read one at a time, when asked for, from the pattern's folder only.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import warnings
from pathlib import Path

import numpy as np

from . import images as io

MOTION_CONVENTIONS = {
    "blurlab": "pixels from shutter open to close, +x right, +y down; already over the shutter",
    "blender": "the Vector pass: X, Y = previous - current and Z, W = current - next position "
    "(both point back in time), pixels, +y up; the shutter is centred on the frame",
    "uv": "UV units per frame: current - previous, +v up, 1 = the image's width (u) or height (v)",
    "ndc": "NDC units per frame: current - previous, +y up, 2 = the image's width or height",
    "unity": "Unity's motion-vector texture (RGHalf): current - previous screen UV per frame, "
    "+v up (UV (0, 0) is the bottom-left); read as 'uv'",
    "unreal": "Unreal's velocity G-buffer: each channel E = V * scale + bias in [0, 1] with V "
    "the current - previous NDC position per frame (+y up), optionally square-root compressed "
    "(UnrealVelocity); E = (0, 0) marks a pixel without velocity, whose motion is the camera's",
}
DEPTH_ENCODINGS = ("linear", "hardware")


@dataclasses.dataclass(frozen=True)
class UnrealVelocity:
    """How an Unreal velocity G-buffer encodes the per-frame NDC velocity V into a channel E in
    [0, 1] (docs/spec.md §16.5): E = D * scale + bias, where D = V, or with `sqrt`,
    D = sign(V) sqrt(2 |V|). The defaults are UE4's encoding; §16.5 says where they come from
    and which is uncertain."""

    scale: float = 0.499 * 0.5
    """E per unit of D: V's range [-2, 2] (twice the screen, for fast motion) fills 0.499 of
    each half of [0, 1], so that no velocity in range is stored as 0."""
    bias: float = 0.5
    """E of a pixel that does not move."""
    sqrt: bool = False
    """Square-root compression of each component (finer steps for slow motion; +-2 stays +-2)."""

    def __post_init__(self):
        if not (isinstance(self.scale, (int, float)) and 0 < self.scale <= 0.5):
            raise ValueError(
                f"blurlab: UnrealVelocity.scale must be in (0, 0.5], not {self.scale!r}"
            )
        if not (isinstance(self.bias, (int, float)) and 0 < self.bias < 1):
            raise ValueError(f"blurlab: UnrealVelocity.bias must be in (0, 1), not {self.bias!r}")
        if not isinstance(self.sqrt, bool):
            raise ValueError(
                f"blurlab: UnrealVelocity.sqrt must be True or False, not {self.sqrt!r}"
            )


# The channel names each buffer may have, in order, one tuple per naming scheme.
_COLOR_CHANNELS = (("R", "G", "B", "A"),)
_MOTION_CHANNELS = (("R", "G", "B", "A"), ("X", "Y", "Z", "W"), ("U", "V"))
_DEPTH_CHANNELS = (("Z",), ("V",), ("Y",), ("R",), ("depth",), ("Depth",))
# Layers looked for in a multi-layer file when the caller names none: Blender's names first.
_DEFAULT_LAYERS = {
    "color": ("Combined", "color", "rgba", ""),
    "depth": ("Depth", "depth", "Z", "z"),
    "motion": ("Vector", "motion", "velocity", "Velocity", "MotionVectors"),
}


def motion_to_blurlab(
    stored: np.ndarray,
    convention: str,
    shutter_fraction: float = 1.0,
    *,
    velocity_encoding: UnrealVelocity | None = None,
    camera_motion=None,
):
    """(H, W, 2 or 4) stored motion in `convention` -> (H, W, 2) blurlab motion over the
    shutter (docs/spec.md §16.1, §16.5). For "unreal", `velocity_encoding` (default
    UnrealVelocity()) says how V was encoded, and `camera_motion`, (H, W, 2) blurlab motion over
    the shutter, is what the pixels marked as without velocity get (default 0, with a warning)."""
    _check_convention(convention, shutter_fraction, velocity_encoding, camera_motion)
    stored = np.asarray(stored, dtype=np.float64)
    need = _width(convention)
    if stored.ndim != 3 or stored.shape[2] < need:
        raise ValueError(
            f"blurlab: {convention!r} motion needs {need} channels, the image has shape "
            f"{stored.shape}"
        )
    h, w = stored.shape[:2]
    s = shutter_fraction
    if convention == "blurlab":
        m = s * stored[..., :2]
    elif convention == "blender":
        # A shutter of s frames centred on the frame spans half of each neighbouring interval;
        # Blender's vectors point back in time (measured, tests/test_blender.py).
        m = 0.5 * s * (stored[..., 0:2] + stored[..., 2:4]) * [-1.0, 1.0]
    elif convention in ("uv", "unity"):
        m = s * stored[..., :2] * [w, -h]
    elif convention == "ndc":
        m = s * stored[..., :2] * [w / 2, -h / 2]
    else:  # unreal
        m = _unreal_to_blurlab(
            stored[..., :2], velocity_encoding or UnrealVelocity(), s, camera_motion
        )
    return m.astype(np.float32)


def _unreal_to_blurlab(encoded, encoding: UnrealVelocity, s: float, camera_motion):
    """Decodes (H, W, 2) E into blurlab motion; the (0, 0) mark gets `camera_motion` or 0."""
    h, w = encoded.shape[:2]
    d = (encoded - encoding.bias) / encoding.scale
    v = np.sign(d) * d * d / 2 if encoding.sqrt else d
    m = s * v * [w / 2, -h / 2]
    # The engine clears its velocity target to 0 and writes only what moves on its own; the
    # rest moves with the camera, which the engine derives from depth and its matrices.
    marked = (encoded[..., 0] == 0) & (encoded[..., 1] == 0)
    if camera_motion is not None:
        fill = np.asarray(camera_motion, dtype=np.float64)
        if fill.shape != (h, w, 2):
            raise ValueError(
                f"blurlab: camera_motion must have shape {(h, w, 2)} (blurlab motion over the "
                f"shutter, like the image), not {fill.shape}"
            )
        return np.where(marked[..., None], fill, m)
    if marked.any():
        warnings.warn(
            f"blurlab: {int(marked.sum())} pixels of the Unreal velocity are (0, 0), the "
            "engine's mark for 'no velocity written, use the camera's motion'; they get motion "
            "0. Pass camera_motion= (blurlab motion over the shutter) to give them the camera's",
            stacklevel=3,
        )
    return np.where(marked[..., None], 0.0, m)


def motion_from_blurlab(
    motion: np.ndarray,
    convention: str,
    shutter_fraction: float = 1.0,
    *,
    velocity_encoding: UnrealVelocity | None = None,
):
    """The inverse of `motion_to_blurlab`: blurlab motion written in `convention` (for the
    "blender" convention both half-frames get the same motion, as for constant velocity; for
    "unreal" E is clipped to [0, 1], as the engine's unorm target clips it)."""
    _check_convention(convention, shutter_fraction, velocity_encoding, None)
    m = np.asarray(motion, dtype=np.float64)
    h, w = m.shape[:2]
    s = shutter_fraction
    if convention == "blurlab":
        out = m / s
    elif convention == "blender":
        half = m / s * [-1.0, 1.0]
        out = np.concatenate([half, half], axis=-1)
    elif convention in ("uv", "unity"):
        out = m / s / [w, -h]
    elif convention == "ndc":
        out = m / s / [w / 2, -h / 2]
    else:  # unreal
        encoding = velocity_encoding or UnrealVelocity()
        v = m / s / [w / 2, -h / 2]
        d = np.sign(v) * np.sqrt(2 * np.abs(v)) if encoding.sqrt else v
        out = np.clip(d * encoding.scale + encoding.bias, 0.0, 1.0)
    return out.astype(np.float32)


def depth_to_linear(stored, encoding: str = "linear", near=None, far=None, reversed_z=False):
    """Stored depth -> blurlab's linear view depth (+inf where nothing was drawn).

    "linear": view-space distance along the view axis, as blurlab stores it; non-positive or
    non-finite values are background. "hardware": a [0, 1] depth buffer of a perspective
    projection with planes `near` < `far` (far may be math.inf); `reversed_z` when 1 is near.
    """
    d = np.asarray(stored, dtype=np.float64)
    if encoding == "linear":
        if near is not None or far is not None or reversed_z:
            raise ValueError("blurlab: near, far and reversed_z go with depth_encoding='hardware'")
        return np.where(np.isfinite(d) & (d > 0), d, np.inf).astype(np.float32)
    if encoding != "hardware":
        raise ValueError(
            f"blurlab: depth_encoding must be one of {DEPTH_ENCODINGS}, not {encoding!r}"
        )
    n, f = _planes(near, far)
    background = 0.0 if reversed_z else 1.0
    d = np.where(np.isfinite(d), np.clip(d, 0.0, 1.0), background)
    if reversed_z:
        d = 1.0 - d
    with np.errstate(divide="ignore"):
        # d = f/(f - n) (1 - n/z) for the standard [0, 1] range, solved for z.
        z = n / (1.0 - d) if math.isinf(f) else n * f / (f - d * (f - n))
    return np.where(d >= 1.0, np.inf, z).astype(np.float32)


def depth_from_linear(z, encoding: str = "linear", near=None, far=None, reversed_z=False):
    """The inverse of `depth_to_linear` (what a renderer with those settings would store)."""
    z = np.asarray(z, dtype=np.float64)
    if encoding == "linear":
        return np.where(np.isfinite(z), z, 0.0).astype(np.float32)
    if encoding != "hardware":
        raise ValueError(
            f"blurlab: depth_encoding must be one of {DEPTH_ENCODINGS}, not {encoding!r}"
        )
    n, f = _planes(near, far)
    ratio = 1.0 if math.isinf(f) else f / (f - n)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(np.isfinite(z), ratio * (1.0 - n / z), 1.0)
    d = np.clip(d, 0.0, 1.0)
    return (1.0 - d if reversed_z else d).astype(np.float32)


def read_exr(
    path=None,
    *,
    color=None,
    depth=None,
    motion=None,
    convention: str = "blurlab",
    shutter_fraction: float = 1.0,
    depth_encoding: str = "linear",
    near=None,
    far=None,
    reversed_z: bool = False,
    shutter=(0.0, 1.0),
    velocity_encoding: UnrealVelocity | None = None,
    camera_motion=None,
) -> dict:
    """The arguments of a Frame (color, depth, motion, shutter) from EXR captures.

    Either `path`, one multi-layer EXR whose `color`, `depth` and `motion` are layer names
    (found by default among Blender's and other common names), or `color`, `depth` and
    `motion` as three file paths. `MOTION_CONVENTIONS`, `motion_to_blurlab` (with
    `velocity_encoding` and `camera_motion`, for "unreal") and `depth_to_linear` say what the
    conventions mean."""
    _check_convention(convention, shutter_fraction, velocity_encoding, camera_motion)
    if path is not None:
        names, pixels = io.read_channels(path)
        source = Path(path).name
        color_px = _layer(names, pixels, color, "color", _COLOR_CHANNELS, 3, source)
        depth_px = _layer(names, pixels, depth, "depth", _DEPTH_CHANNELS, 1, source)
        motion_px = _layer(
            names, pixels, motion, "motion", _MOTION_CHANNELS, _width(convention), source
        )
    else:
        if color is None or depth is None or motion is None:
            raise ValueError(
                "blurlab.Frame.from_exr: give one multi-layer file, or color=, depth= and "
                "motion= as three EXR paths"
            )
        color_px = _file(color, "color", _COLOR_CHANNELS, 3)
        depth_px = _file(depth, "depth", _DEPTH_CHANNELS, 1)
        motion_px = _file(motion, "motion", _MOTION_CHANNELS, _width(convention))
    shapes = {
        what: a.shape[:2]
        for what, a in (("color", color_px), ("depth", depth_px), ("motion", motion_px))
    }
    if len(set(shapes.values())) != 1:
        raise ValueError(f"blurlab.Frame.from_exr: the images differ in size: {shapes}")
    return {
        "color": _rgba(color_px),
        "depth": depth_to_linear(depth_px[..., 0], depth_encoding, near, far, reversed_z),
        "motion": motion_to_blurlab(
            motion_px,
            convention,
            shutter_fraction,
            velocity_encoding=velocity_encoding,
            camera_motion=camera_motion,
        ),
        "shutter": tuple(float(t) for t in shutter),
    }


def read_color(path, layer: str | None = None) -> np.ndarray:
    """(H, W, 4) linear colour of an image file: a reference or an engine's blurred output. A
    multi-layer file gives its `layer` (default: Blender's Combined, or another common colour
    layer's name), a plain one its R, G, B (and A) channels; alpha is 1 where there is none."""
    names, pixels = io.read_channels(path)
    return _rgba(_layer(names, pixels, layer, "color", _COLOR_CHANNELS, 3, Path(path).name))


def _rgba(color: np.ndarray) -> np.ndarray:
    if color.shape[2] == 4:
        return color
    return np.concatenate([color, np.ones(color.shape[:2] + (1,), np.float32)], axis=2)


# sequence(): the frame number in a pattern's file name, and the most frames one pattern gives.
FRAME_NUMBER = "#"
MAX_SEQUENCE_FRAMES = 4096
# What a sequence's frames are read with: read_exr's keywords, the layer names among them.
READ_OPTIONS = (
    "color",
    "depth",
    "motion",
    "convention",
    "shutter_fraction",
    "depth_encoding",
    "near",
    "far",
    "reversed_z",
    "shutter",
    "velocity_encoding",
    "camera_motion",
)


@dataclasses.dataclass(frozen=True)
class CapturedSequence:
    """The frames of one captured shot, as files (`sequence` makes it). Nothing is read until
    a frame is asked for, and then that frame's file alone: ``bl.Frame(**shot[i])`` is frame
    i's G-buffer, ``shot.color(i)`` its colour alone (a reference's or an engine's output)."""

    pattern: str
    paths: tuple[Path, ...]
    numbers: tuple[int, ...]  # each file's frame number, consecutive
    options: dict = dataclasses.field(default_factory=dict, repr=False, compare=False)

    def __len__(self) -> int:
        return len(self.paths)

    def __getitem__(self, index: int) -> dict:
        """Frame `index`'s arguments of a bl.Frame, as `read_exr` reads them."""
        return read_exr(self.paths[index], **self.options)

    def __iter__(self):
        return (self[i] for i in range(len(self)))

    def color(self, index: int) -> np.ndarray:
        """Frame `index`'s (H, W, 4) colour (`read_color`, from the layer named by the
        option `color`)."""
        return read_color(self.paths[index], self.options.get("color"))

    def size(self) -> tuple[int, int]:
        """(width, height) of every frame, read from the files' headers; a ValueError names
        the first file of another size."""
        first = io.image_size(self.paths[0])
        for path in self.paths[1:]:
            here = io.image_size(path)
            if here != first:
                raise ValueError(
                    f"blurlab.io.capture: {path.name} is {here[0]}x{here[1]}, but "
                    f"{self.paths[0].name} of the same sequence is {first[0]}x{first[1]}"
                )
        return first


def sequence(pattern: str | os.PathLike, **options) -> CapturedSequence:
    """A captured sequence from the files `pattern` names (docs/spec.md §16.6).

    The pattern is a path whose file name holds one run of ``#``, the frame number, padded
    with zeros to the run's length at least: ``shots/shot.####.exr`` matches shot.0001.exr,
    shot.0002.exr, ... and shot.10000.exr, as Blender names its frames. The frames are the
    matching regular files of the pattern's folder (never a link, a sub-folder or another
    folder), in frame order, consecutive, at most MAX_SEQUENCE_FRAMES. A path without ``#``
    is a sequence of that one file. `options`: how each frame is read, read_exr's keywords
    (convention, shutter_fraction, depth_encoding, the layer names color, depth and motion,
    ...), checked now; each frame is read only when it is asked for (CapturedSequence)."""
    unknown = sorted(set(options) - set(READ_OPTIONS))
    if unknown:
        raise TypeError(
            f"blurlab.io.capture.sequence: unknown options {unknown}; it takes {list(READ_OPTIONS)}"
        )
    text = os.fspath(pattern)
    try:
        _check_convention(
            options.get("convention", "blurlab"),
            options.get("shutter_fraction", 1.0),
            options.get("velocity_encoding"),
            options.get("camera_motion"),
        )
    except ValueError as error:
        raise ValueError(
            f"blurlab.io.capture.sequence({text!r}): {_without_prefix(error)}"
        ) from None
    for layer in ("color", "depth", "motion"):
        if options.get(layer) is not None and not isinstance(options[layer], str):
            raise TypeError(
                f"blurlab.io.capture.sequence: {layer} is a layer's name, not {options[layer]!r}"
            )
    numbers, paths = _frame_files(text)
    return CapturedSequence(text, tuple(paths), tuple(numbers), dict(options))


def _without_prefix(error: Exception) -> str:
    return str(error).removeprefix("blurlab: ")


def _frame_files(pattern: str) -> tuple[list[int], list[Path]]:
    """The frame numbers and files of `pattern`, in frame order."""
    folder_text, name = os.path.split(pattern)
    if FRAME_NUMBER in folder_text:
        raise ValueError(
            f"blurlab.io.capture.sequence: {pattern!r}: the frame number ({FRAME_NUMBER}) goes "
            "in the file name, not in a folder's"
        )
    runs = re.findall(f"{FRAME_NUMBER}+", name)
    if not runs:
        path = Path(pattern)
        if not path.is_file():
            raise FileNotFoundError(f"blurlab.io.capture.sequence: no such file: {pattern}")
        return [0], [path]
    if len(runs) > 1:
        raise ValueError(
            f"blurlab.io.capture.sequence: {name!r} has {len(runs)} runs of {FRAME_NUMBER}; one "
            "run is the frame number (shot.####.exr)"
        )
    width = len(runs[0])
    prefix, suffix = name.split(runs[0])
    matcher = re.compile(re.escape(prefix) + r"([0-9]+)" + re.escape(suffix))
    folder = Path(folder_text or ".")
    if not folder.is_dir():
        raise FileNotFoundError(f"blurlab.io.capture.sequence: no such folder: {folder}")
    found: dict[int, Path] = {}
    with os.scandir(folder) as entries:
        for entry in entries:
            matched = matcher.fullmatch(entry.name)
            digits = matched.group(1) if matched else ""
            # Padded to the run's width exactly, or longer without a leading zero.
            if not digits or len(digits) < width or (len(digits) > width and digits[0] == "0"):
                continue
            if not entry.is_file(follow_symlinks=False):
                raise ValueError(
                    f"blurlab.io.capture.sequence: {folder / entry.name} matches {name!r} but is "
                    "not a regular file (a link or a folder); frames are read from the "
                    "pattern's folder's own files only"
                )
            found[int(digits)] = folder / entry.name
            if len(found) > MAX_SEQUENCE_FRAMES:
                raise ValueError(
                    f"blurlab.io.capture.sequence: {pattern!r} matches more than "
                    f"{MAX_SEQUENCE_FRAMES} files, the most one sequence reads"
                )
    if not found:
        raise FileNotFoundError(
            f"blurlab.io.capture.sequence: no file in {folder} matches {name!r} ({FRAME_NUMBER} "
            f"is the frame number, {width} digits or more)"
        )
    numbers = sorted(found)
    missing = sorted(set(range(numbers[0], numbers[-1] + 1)) - set(numbers))
    if missing:
        first = f"{prefix}{missing[0]:0{width}d}{suffix}"
        raise FileNotFoundError(
            f"blurlab.io.capture.sequence: {pattern!r} has frames {numbers[0]} to {numbers[-1]} "
            f"but {len(missing)} missing, the first {folder / first}; a sequence's frames are "
            "consecutive"
        )
    return numbers, [found[n] for n in numbers]


def _check_convention(convention: str, shutter_fraction: float, velocity_encoding, camera_motion):
    if convention not in MOTION_CONVENTIONS:
        raise ValueError(
            f"blurlab: motion convention must be one of {tuple(MOTION_CONVENTIONS)}, "
            f"not {convention!r}"
        )
    if not (isinstance(shutter_fraction, (int, float)) and 0 < shutter_fraction <= 1):
        raise ValueError(f"blurlab: shutter_fraction must be in (0, 1], not {shutter_fraction!r}")
    if convention != "unreal" and (velocity_encoding is not None or camera_motion is not None):
        raise ValueError(
            f"blurlab: velocity_encoding and camera_motion go with convention='unreal', "
            f"not {convention!r}"
        )
    if velocity_encoding is not None and not isinstance(velocity_encoding, UnrealVelocity):
        raise ValueError(
            "blurlab: velocity_encoding must be a blurlab.io.capture.UnrealVelocity, not "
            f"{type(velocity_encoding).__name__}"
        )


def _planes(near, far) -> tuple[float, float]:
    try:
        n, f = float(near), float(far)
    except (TypeError, ValueError):
        raise ValueError(
            "blurlab: depth_encoding='hardware' needs near and far (far may be math.inf)"
        ) from None
    if not (math.isfinite(n) and 0 < n < f):
        raise ValueError(f"blurlab: hardware depth needs 0 < near < far, got {near}, {far}")
    return n, f


def _width(convention: str) -> int:
    return 4 if convention == "blender" else 2


def _pick(names: list[str], orders, count: int):
    """Indices of the first `count` channels of one of the naming schemes in `orders` (and up
    to 4 in all where the scheme has more, for colour's alpha), or None."""
    last = [n.rsplit(".", 1)[-1] for n in names]
    for order in orders:
        found = [last.index(c) for c in order[:count] if c in last]
        if len(found) == count:
            return found + [last.index(c) for c in order[count:] if c in last][: max(0, 4 - count)]
    return None


def _layer(names, pixels, layer, what, suffixes, count, source):
    wanted = [layer] if layer is not None else list(_DEFAULT_LAYERS[what])
    for name in wanted:
        members = [i for i, n in enumerate(names) if _in_layer(n, name, count == 1)]
        chosen = _pick([names[i] for i in members], suffixes, count) if members else None
        if chosen is None and len(members) == count:
            chosen = list(range(count))
        if chosen is not None:
            keep = chosen[:4] if what == "color" else chosen[:count]
            return pixels[..., [members[i] for i in keep]]
    raise ValueError(
        f"blurlab.Frame.from_exr: {source} has no {what} layer "
        f"{'named ' + repr(layer) if layer is not None else 'among ' + repr(wanted)} with "
        f"{count} channel{'s' if count > 1 else ''}; its channels are {names[:24]}"
    )


def _in_layer(channel: str, layer: str, single: bool) -> bool:
    """Whether `channel` ("<layer>.<name>", maybe behind a view-layer prefix such as Blender's
    "ViewLayer.") belongs to `layer`; a one-channel layer may also be the channel itself."""
    prefix = channel.rsplit(".", 1)[0] if "." in channel else ""
    if prefix == layer or prefix.endswith("." + layer):
        return True
    return single and (channel == layer or channel.endswith("." + layer))


def _file(path, what, suffixes, count):
    names, pixels = io.read_channels(path)
    chosen = _pick(names, suffixes, count)
    if chosen is None:
        if pixels.shape[2] < count:
            raise ValueError(
                f"blurlab.Frame.from_exr: {Path(path).name} has {pixels.shape[2]} channels; "
                f"{what} needs {count}"
            )
        chosen = list(range(count))
    keep = chosen[:4] if what == "color" else chosen[:count]
    return pixels[..., keep]
