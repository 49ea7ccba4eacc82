"""Sequences (docs/spec.md §21): consecutive frames of a scene at a frame rate and shutter angle,
each with its own shutter, sub-pixel jitter and reference; a method, TAA (blurlab.taa) or both,
in either order, run over them; the result measured frame by frame and over time.

``bl.sequence(ctx, scene, size, fps=60, frames=16, shutter_angle=180)`` renders the references
and returns a `Sequence`; ``Sequence.run(method, order, taa={...}, **params)`` returns a
`SequenceRun` with the output frames, the per-frame scores and the temporal ones.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np

from . import metrics, video
from .blur_scales import scaled_scene
from .context import Context, Texture
from .frame import Frame
from .methods import blur, method, method_instant
from .render import check_size, render_targets
from .scene import Scene
from .shutters import shutter
from .sizes import DEFAULT_SIZE
from .taa import taa, taa_values

JITTERS = ("halton", "none")
# Where TAA goes relative to the method (docs/spec.md §21.4): "none" runs the method alone.
ORDERS = ("none", "blur_then_taa", "taa_then_blur", "blur_in_history")
MAX_FRAMES = 4096
DEFAULT_METRICS = ("psnr", "temporal_instability")


def radical_inverse(index: int, base: int) -> float:
    """The Halton point of `index` in `base`: its digits mirrored about the radix point."""
    value, scale = 0.0, 1.0 / base
    while index > 0:
        index, digit = divmod(index, base)
        value += digit * scale
        scale /= base
    return value


def jitter_positions(frames: int, jitter: str) -> np.ndarray:
    """(frames, 2) sample positions inside the pixel, from its top-left corner: Halton (2, 3)
    points 1, 2, … ("halton"; index 0 is the corner, so engines start at 1) or the centre."""
    if jitter == "none":
        return np.full((frames, 2), 0.5)
    return np.array([[radical_inverse(i, 2), radical_inverse(i, 3)] for i in range(1, frames + 1)])


def still(scene: Scene, time: float) -> Scene:
    """`scene` with every object, skeleton and the camera held where they are at `time`:
    motion zeroed, for the convergence of TAA on a still image."""
    held = dataclasses.replace(
        scene,
        objects=[dataclasses.replace(obj, motion_blur=0.0) for obj in scene.objects],
        camera_motion_blur=0.0,
    )
    return scaled_scene(held, (time, time))  # blur scale 0 about `time`: fixed at `time`


@dataclass
class Sequence:
    """Frames i = 0 … N−1 of a scene: frame i is shown at `times[i]`, its shutter is
    `shutters[i]`, its G-buffer is rendered with its sub-pixel position `positions[i]`, and
    `references[i]` is the (H, W, 4) reference over its shutter (docs/spec.md §21.1)."""

    ctx: Context = field(repr=False)
    scene: Scene = field(repr=False)
    size: tuple[int, int]
    fps: float
    shutter_angle: float
    times: np.ndarray
    shutters: np.ndarray  # (N, 2) seconds
    positions: np.ndarray  # (N, 2) inside the pixel, from its top-left corner
    references: np.ndarray = field(repr=False)  # (N, H, W, 4) float32
    reference_samples: int
    antialias: bool

    @property
    def frames(self) -> int:
        return len(self.times)

    def jitter(self, i: int) -> tuple[float, float]:
        """Frame i's sub-pixel shift for ctx.render (docs/spec.md §12)."""
        dx, dy = 0.5 - self.positions[i]
        return float(dx), float(dy)

    def frame(self, i: int, instant: str = "center") -> Frame:
        """Frame i's G-buffer at `instant` of its shutter, jittered."""
        return self.ctx.render(
            self.scene, self.size, tuple(self.shutters[i]), instant, jitter=self.jitter(i)
        )

    def motion_from_previous(self, i: int, time: float) -> Texture:
        """(H, W, 2) pooled texture: the screen motion, in pixels, from one frame interval
        before `time` to `time` of the point each of frame i's pixels shows at `time`: the
        motion buffer TAA reprojects by. The caller recycles it."""
        interval = (time - 1.0 / self.fps, time)
        targets, _, _ = render_targets(
            self.ctx, self.scene, self.size, interval, time, 0, self.jitter(i), timers=False
        )
        motion = targets.pop("motion")
        self.ctx.recycle(*targets.values())
        return motion

    def run(
        self,
        method_name: str | None = None,
        order: str = "none",
        taa: dict | None = None,
        metrics: tuple[str, ...] = DEFAULT_METRICS,
        **params,
    ) -> SequenceRun:
        """Runs method `method_name` (None: the G-buffer's colour as it is) with `params`
        on every frame, with TAA (parameters `taa`, blurlab.taa.PARAMS) placed by `order`
        (docs/spec.md §21.4), and scores every frame and the whole against the references with
        the registered `metrics`."""
        return run_sequence(self, method_name, order, taa or {}, metrics, params)


@dataclass
class SequenceRun:
    """What a run over a sequence gave: the (N, H, W, 4) output (its alpha is the frame's), the
    scores (per-frame metrics as (N,) arrays, sequence metrics as numbers) and per-frame GPU
    milliseconds of the method and of TAA."""

    method: str | None
    params: dict
    order: str
    taa: dict
    color: np.ndarray = field(repr=False)
    references: np.ndarray = field(repr=False)
    scores: dict
    blur_ms: np.ndarray
    taa_ms: np.ndarray
    fps: float

    def side_by_side(self, frames=None) -> np.ndarray:
        """(n, H, 2W, 4): output frames (all, or the indices `frames`) with their references to
        their right."""
        chosen = slice(None) if frames is None else np.asarray(frames, int)
        return np.concatenate([self.color[chosen], self.references[chosen]], axis=2)

    def worst_frames(self, metric: str = "psnr", count: int = 8) -> np.ndarray:
        """The indices of the `count` frames that score worst by the per-frame `metric`, in
        their order in the sequence."""
        values = self.scores.get(metric)
        if values is None or np.ndim(values) != 1:
            raise ValueError(f"blurlab: {metric!r} is not a per-frame score of this run")
        goodness = np.asarray(metrics.get(metric).goodness(values), float)
        return np.sort(np.argsort(goodness, kind="stable")[: max(1, count)])

    def write(self, path, frames=None):
        """The output beside the reference (`side_by_side`) as a folder of EXRs, an .mp4, a
        looping .gif or .webp (blurlab.video), at the sequence's frame rate."""
        return video.write(path, self.side_by_side(frames), self.fps)


def sequence(
    ctx: Context,
    scene: Scene,
    size=DEFAULT_SIZE,
    fps: float = 60.0,
    frames: int = 16,
    shutter_angle: float = 180.0,
    jitter: str = "halton",
    reference_samples: int = 64,
    antialias: bool = True,
    seed: int = 0,
) -> Sequence:
    """`frames` consecutive frames of `scene` at `fps` with a `shutter_angle` (degrees) shutter
    centred on each frame's time (docs/spec.md §15.2), the frames centred on the scene's
    shutter so that the middle one is the single-frame case. Each frame's reference is
    ``ctx.reference`` over its shutter with `reference_samples` sub-frames and the same `seed`
    (still pixels do not flicker in it); ``antialias=True`` makes it the box-filtered image
    jittered frames converge to, ``antialias=False`` samples pixel centres and needs
    ``jitter="none"``. `jitter` "halton" moves frame i's samples to Halton (2, 3) point i + 1
    inside the pixel, as engines do under TAA."""
    if not isinstance(ctx, Context):
        raise TypeError(f"blurlab: sequence needs a blurlab Context, not {type(ctx).__name__}")
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab: sequence needs a blurlab Scene, not {type(scene).__name__}")
    size = check_size(size, ctx.max_texture_size)
    if jitter not in JITTERS:
        raise ValueError(f"blurlab: jitter must be one of {JITTERS}, not {jitter!r}")
    if not isinstance(antialias, bool):
        raise ValueError(f"blurlab: antialias must be True or False, not {antialias!r}")
    if not antialias and jitter != "none":
        raise ValueError(
            "blurlab: antialias=False samples pixel centres, which jittered frames do not: "
            "pass jitter='none', or keep antialias=True"
        )
    times, shutters = frame_shutters(scene, fps, frames, shutter_angle)
    references = np.stack(
        [
            ctx.reference(
                scene,
                size,
                tuple(s),
                reference_samples,
                seed=seed,
                progress=False,
                antialias=antialias,
            ).color
            for s in shutters
        ]
    )
    return Sequence(
        ctx,
        scene,
        size,
        float(fps),
        float(shutter_angle),
        times,
        shutters,
        jitter_positions(frames, jitter),
        references,
        reference_samples,
        antialias,
    )


def frame_shutters(
    scene: Scene, fps: float = 60.0, frames: int = 16, shutter_angle: float = 180.0
) -> tuple[np.ndarray, np.ndarray]:
    """(times, shutters) of a sequence's `frames` frames: frame i at the scene's shutter
    centre + (i - (frames - 1) / 2) / fps, its shutter `shutter_angle` degrees of the frame
    interval centred there (docs/spec.md §21.1)."""
    if isinstance(frames, bool) or not isinstance(frames, Integral) or not 0 < frames <= MAX_FRAMES:
        raise ValueError(f"blurlab: frames must be an integer in 1..{MAX_FRAMES}, not {frames!r}")
    if isinstance(fps, bool) or not isinstance(fps, Real) or not 0 < fps < math.inf:
        raise ValueError(f"blurlab: fps must be a finite number > 0, not {fps!r}")
    middle = 0.5 * (scene.shutter[0] + scene.shutter[1])
    times = middle + (np.arange(frames) - (frames - 1) / 2) / fps
    # shutter() checks the angle and places the shutter on each frame's time.
    shutters = np.array([shutter(fps, shutter_angle, t * fps) for t in times])
    return times, shutters


def frame_scenes(
    scene: Scene, fps: float = 60.0, frames: int = 16, shutter_angle: float = 180.0
) -> list[Scene]:
    """The frames of a sequence of `scene` as scenes of their own, each with its frame's
    shutter (frame_shutters) and named "NAME@i": what a single-frame tool such as
    bl.recommend_set measures frame by frame, to choose one configuration for the sequence
    (docs/spec.md §23.2)."""
    if not isinstance(scene, Scene):
        raise TypeError(f"blurlab: frame_scenes needs a blurlab Scene, not {type(scene).__name__}")
    _, shutters = frame_shutters(scene, fps, frames, shutter_angle)
    return [
        dataclasses.replace(scene, shutter=(float(a), float(b)), name=f"{scene.name}@{i}")
        for i, (a, b) in enumerate(shutters)
    ]


def run_sequence(
    seq: Sequence, method_name, order: str, taa_given: dict, names, params: dict
) -> SequenceRun:
    """Sequence.run: frame by frame, the method and TAA in `order`, then the scores."""
    if order not in ORDERS:
        raise ValueError(f"blurlab: order must be one of {ORDERS}, not {order!r}")
    names = metrics.check_names(names, "blurlab: Sequence.run", sequences=True)
    m = None if method_name is None else method(method_name)
    if m is not None and not m.sweepable:
        raise ValueError(f"blurlab: {m.name} blends frames itself; a sequence runs it per frame")
    if m is not None and m.renders and order in ("taa_then_blur", "blur_in_history"):
        raise ValueError(
            f"blurlab: {m.name} renders its own sub-frames, so TAA cannot come before it: "
            "use order 'none' or 'blur_then_taa'"
        )
    if m is None and params:
        raise TypeError(f"blurlab: parameters {sorted(params)} need a method")
    if m is None and order == "blur_in_history":
        raise ValueError("blurlab: order 'blur_in_history' needs a method")
    taa_params = taa_values(**taa_given)
    instant = "center" if m is None else method_instant(m.name, params)
    height, width = seq.size[1], seq.size[0]
    color = np.empty((seq.frames, height, width, 4), np.float32)
    blur_ms, taa_ms = np.zeros(seq.frames), np.zeros(seq.frames)
    history: Texture | None = None
    used: dict = {}
    for i in range(seq.frames):
        frame = seq.frame(i, instant)
        step = FrameStep(seq.ctx, m, params, taa_params)
        if order != "none" and history is not None:
            step.motion = seq.motion_from_previous(i, frame.time)
        image, new_history = step.run(frame, order, history)
        color[i] = image
        color[i, ..., 3] = frame.color[..., 3]
        blur_ms[i], taa_ms[i] = step.blur_ms, step.taa_ms
        used = step.used
        seq.ctx.recycle(*[t for t in (history, step.motion) if t is not None])
        history = new_history
    if history is not None:
        seq.ctx.recycle(history)
    return SequenceRun(
        method_name,
        used,
        order,
        taa_params if order != "none" else {},
        color,
        seq.references,
        scores(names, seq.references, color, seq.ctx),
        blur_ms,
        taa_ms,
        seq.fps,
    )


@dataclass
class FrameStep:
    """One frame of a run: the method (None: none) and TAA in an order (docs/spec.md §21.4)."""

    ctx: Context
    method: object  # the registered Method, or None
    params: dict
    taa_params: dict
    motion: Texture | None = None  # from the previous frame to this one; None on the first
    used: dict = field(default_factory=dict)
    blur_ms: float = 0.0
    taa_ms: float = 0.0

    def blurred(self, frame: Frame):
        result = blur(self.ctx, frame, self.method.name, **self.params)
        self.used, self.blur_ms = result.params, result.total_ms
        return result

    def resolved(self, current: Texture, history: Texture | None) -> Texture:
        timings: dict = {}
        motion = current if self.motion is None else self.motion  # read only with a history
        out = taa(self.ctx, current, motion, history, timings, **self.taa_params)
        self.taa_ms = timings["taa"].ms
        return out

    def run(self, frame: Frame, order: str, history: Texture | None):
        """(this frame's output (H, W, 4), the history the next frame reprojects or None)."""
        m = self.method
        if order == "none":
            return (self.blurred(frame).color if m is not None else frame.color), None
        if order == "blur_then_taa":
            # The result is held until TAA has read it: freed, its texture returns to the pool
            # that TAA's output is taken from.
            result = self.blurred(frame) if m is not None else None
            current = frame.textures["color"] if result is None else result.textures["color"]
            resolved = self.resolved(current, history)
            return resolved.download(), resolved
        resolved = self.resolved(frame.textures["color"], history)
        antialiased = resolved.download()
        if m is None:
            return antialiased, resolved
        image = self.blurred(with_color(self.ctx, frame, antialiased)).color
        if order == "blur_in_history":  # the next frame reprojects the blurred image
            fed_back = np.concatenate([image[..., :3], antialiased[..., 3:]], axis=2)
            resolved.upload(np.ascontiguousarray(fed_back))
        return image, resolved


def with_color(ctx: Context, frame: Frame, color: np.ndarray) -> Frame:
    """`frame` with another (H, W, 4) colour (its alpha kept): what a method after TAA reads.
    It shares the frame's other textures, so it lives no longer than the frame."""
    color = np.concatenate([color[..., :3], frame.color[..., 3:]], axis=2)
    textures = {**frame.textures, "color": ctx.upload(color)}
    return dataclasses.replace(frame, color=color, textures=textures)


def scores(names, references: np.ndarray, color: np.ndarray, ctx: Context | None = None) -> dict:
    """{metric: value}: the sequence metrics of `names` as numbers, the others per frame as
    (N,) arrays (docs/spec.md §21.3). With `ctx`, per-frame metrics that have a GPU
    implementation run on it (within its registered tolerance of the NumPy one)."""
    over_time = [n for n in names if metrics.get(n).sequence]
    on_gpu = [n for n in names if ctx is not None and metrics.get(n).gpu is not None]
    on_cpu = [n for n in names if n not in over_time and n not in on_gpu]
    result = metrics.per_frame(on_cpu, references, color)
    if on_gpu:
        result |= gpu_per_frame(ctx, on_gpu, references, color)
    for name in over_time:
        result[name] = metrics.get(name).numpy(references, color) if len(color) > 1 else math.nan
    return {name: result[name] for name in names}


def gpu_per_frame(ctx: Context, names, references: np.ndarray, color: np.ndarray) -> dict:
    """{metric: (N,) values} of metrics with a GPU implementation, frame by frame."""
    shape = references.shape[1:]
    reference, output = ctx.pooled(shape), ctx.pooled(shape)
    values = {name: np.empty(len(color)) for name in names}
    try:
        for i in range(len(color)):
            reference.upload(np.ascontiguousarray(references[i], np.float32))
            output.upload(np.ascontiguousarray(color[i], np.float32))
            for name in names:
                values[name][i] = metrics.get(name).gpu(ctx, reference, output)
    finally:
        ctx.recycle(reference, output)
    return values
