"""Sequences (docs/spec.md §21): consecutive frames of a scene at a frame rate and shutter angle,
each with its own shutter, sub-pixel jitter and reference; a method, TAA (temporal/taa.py) or
both, in either order, run over them; the result measured frame by frame and over time.

``bl.sequence(ctx, scene, size, fps=60, frames=16, shutter_angle=180)`` renders the references
and returns a `Sequence`; ``Sequence.run(method, order, taa={...}, **params)`` returns a
`SequenceRun` with the output frames, the per-frame scores and the temporal ones.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import weakref
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np

from .. import metrics
from ..core.context import Context
from ..core.frame import Frame
from ..core.gl import Texture
from ..core.graph import Node, run_graph, wire
from ..core.render import check_size, render_targets
from ..io import video
from ..methods import blur, method, method_instant
from ..scene.blur_scales import scaled_scene
from ..scene.model import Scene
from ..scene.shutters import shutter
from ..sizes import DEFAULT_SIZE
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
    `references[i]` is the (H, W, 4) reference over its shutter (docs/spec.md §21.1). The
    references stay on the GPU (`reference_textures`); `references` downloads them when first
    read."""

    ctx: Context = field(repr=False)
    scene: Scene = field(repr=False)
    size: tuple[int, int]
    fps: float
    shutter_angle: float
    times: np.ndarray
    shutters: np.ndarray  # (N, 2) seconds
    positions: np.ndarray  # (N, 2) inside the pixel, from its top-left corner
    # The N references (blurlab.core.references.Reference): their (H, W, 4) float32 textures stay on
    # the GPU as long as the sequence does.
    reference_renders: list = field(repr=False)
    reference_samples: int
    antialias: bool

    @property
    def reference_textures(self) -> list[Texture]:
        return [reference.texture for reference in self.reference_renders]

    @functools.cached_property
    def references(self) -> np.ndarray:
        """(N, H, W, 4) float32: the references, downloaded on first use."""
        return np.stack([texture.download() for texture in self.reference_textures])

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
        on every frame, with TAA (parameters `taa`, blurlab.temporal.taa.PARAMS) placed by `order`
        (docs/spec.md §21.4), and scores every frame and the whole against the references with
        the registered `metrics`."""
        return run_sequence(self, method_name, order, taa or {}, metrics, params)


@dataclass
class SequenceRun:
    """What a run over a sequence gave: the output frames (their alpha is the frame's), on the
    GPU in `output_textures` and downloaded as the (N, H, W, 4) `color` when first read; the
    scores (per-frame metrics as (N,) arrays, sequence metrics as numbers); per frame, its MSE
    and its pair's temporal instability (frame i against i − 1, NaN for frame 0), both reduced
    on the GPU; and per-frame GPU milliseconds of the method and of TAA."""

    method: str | None
    params: dict
    order: str
    taa: dict
    sequence: Sequence = field(repr=False)
    output_textures: list = field(repr=False)
    scores: dict
    frame_mse: np.ndarray = field(repr=False)
    pair_instability: np.ndarray = field(repr=False)
    blur_ms: np.ndarray
    taa_ms: np.ndarray
    fps: float

    @functools.cached_property
    def color(self) -> np.ndarray:
        """(N, H, W, 4) float32: the output frames, downloaded on first use."""
        return np.stack([texture.download() for texture in self.output_textures])

    @property
    def references(self) -> np.ndarray:
        return self.sequence.references

    def instability_after(self, warmup: int = 0) -> float:
        """temporal_instability over frames warmup … N − 1 (their N − 1 − warmup pairs)."""
        pairs = self.pair_instability[warmup + 1 :]
        return float(pairs.mean()) if pairs.size else math.nan

    def side_by_side(self, frames=None) -> np.ndarray:
        """(n, H, 2W, 4): output frames (all, or the indices `frames`) with their references to
        their right."""
        if frames is None:
            return np.concatenate([self.color, self.references], axis=2)
        chosen = np.asarray(frames, int)
        # only the chosen frames cross to the host (a study shows a few of each run's frames)
        outputs = (
            self.color[chosen]
            if "color" in self.__dict__
            else np.stack([self.output_textures[i].download() for i in chosen.tolist()])
        )
        return np.concatenate([outputs, self.references[chosen]], axis=2)

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
        looping .gif or .webp (blurlab.io.video), at the sequence's frame rate."""
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
    references = [
        ctx.reference(
            scene,
            size,
            tuple(s),
            reference_samples,
            seed=seed,
            progress=False,
            antialias=antialias,
        )
        for s in shutters
    ]
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
    ctx, count = seq.ctx, seq.frames
    references = seq.reference_textures
    # Per frame nothing but scalars comes back to the host (docs/spec.md §21.3): the output
    # stays a texture, and its scores are reductions on the GPU.
    on_gpu = [n for n in names if not metrics.get(n).sequence and metrics.get(n).gpu is not None]
    per_frame = {name: np.empty(count) for name in on_gpu}
    mse, instability = np.empty(count), np.full(count, math.nan)
    blur_ms, taa_ms = np.zeros(count), np.zeros(count)
    outputs: list[Texture] = []
    history: Texture | None = None
    used: dict = {}
    for i in range(count):
        frame = seq.frame(i, instant)
        step = FrameStep(ctx, m, params, taa_params)
        if order != "none" and history is not None:
            step.motion = seq.motion_from_previous(i, frame.time)
        output, new_history = step.run(frame, order, history)
        mse[i] = metrics.gpu_mse(ctx, references[i], output)
        for name in on_gpu:
            per_frame[name][i] = metrics.get(name).gpu(ctx, references[i], output)
        if i > 0:
            instability[i] = metrics.gpu_pair_instability(
                ctx, output, outputs[-1], references[i], references[i - 1]
            )
        outputs.append(output)
        blur_ms[i], taa_ms[i] = step.blur_ms, step.taa_ms
        used = step.used
        ctx.recycle(*[t for t in (history, step.motion) if t is not None])
        history = new_history
    if history is not None:
        ctx.recycle(history)
    run = SequenceRun(
        method_name,
        used,
        order,
        taa_params if order != "none" else {},
        seq,
        outputs,
        {},
        mse,
        instability,
        blur_ms,
        taa_ms,
        seq.fps,
    )
    weakref.finalize(run, ctx.recycle, *outputs)
    run.scores = scores(names, run, per_frame)
    return run


@dataclass
class FrameStep:
    """One frame of a run: the method (None: none) and TAA in an order (docs/spec.md §21.4), on
    the frame's textures."""

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
        """(this frame's output, a new (H, W, 4) texture with the frame's alpha; the history
        the next frame reprojects, or None)."""
        m, ctx = self.method, self.ctx
        alpha = frame.textures["color"]
        if order == "none":
            result = self.blurred(frame) if m is not None else None
            image = alpha if result is None else result.textures["color"]
            return with_alpha(ctx, image, alpha), None
        if order == "blur_then_taa":
            # The result is held until TAA has read it: freed, its texture returns to the pool
            # that TAA's output is taken from.
            result = self.blurred(frame) if m is not None else None
            current = alpha if result is None else result.textures["color"]
            resolved = self.resolved(current, history)
            return with_alpha(ctx, resolved, alpha), resolved
        resolved = self.resolved(alpha, history)
        if m is None:
            return with_alpha(ctx, resolved, alpha), resolved
        antialiased = with_color(ctx, frame, resolved)
        image = self.blurred(antialiased).textures["color"]
        output = with_alpha(ctx, image, alpha)
        if order == "blur_in_history":  # the next frame reprojects the blurred image
            fed_back = with_alpha(ctx, image, resolved)
            ctx.recycle(resolved)
            resolved = fed_back
        return output, resolved


RGB_ALPHA = Node("rgb_alpha", "passes/rgb_alpha.comp")


def with_alpha(ctx: Context, rgb: Texture, alpha: Texture) -> Texture:
    """A new pooled (H, W, 4) texture: `rgb`'s colour with `alpha`'s alpha
    (passes/rgb_alpha.comp, on the pass graph)."""
    wired = ctx.cached(("sequence graph", RGB_ALPHA), lambda: wire(ctx, [RGB_ALPHA], "compute"))
    return run_graph(ctx, wired, {"rgb": rgb, "alpha": alpha}, keep=("result",))["result"]


def with_color(ctx: Context, frame: Frame, color: Texture) -> Frame:
    """`frame` with another colour texture (its alpha kept): what a method after TAA reads.
    It shares the frame's other textures, so it lives no longer than the frame."""
    combined = with_alpha(ctx, color, frame.textures["color"])
    derived = frame.with_textures({**frame.textures, "color": combined})
    weakref.finalize(derived, ctx.recycle, combined)
    return derived


def scores(names, run: SequenceRun, on_gpu: dict) -> dict:
    """{metric: value}: the sequence metrics of `names` as numbers, the others per frame as
    (N,) arrays (docs/spec.md §21.3). `on_gpu` holds the per-frame ones already reduced on the
    GPU; temporal_instability comes from the run's pairs; any other metric downloads the
    frames and the references and runs its NumPy definition."""
    result = dict(on_gpu)
    over_time = [n for n in names if metrics.get(n).sequence]
    on_cpu = [n for n in names if n not in over_time and n not in on_gpu]
    if on_cpu:
        result |= metrics.per_frame(on_cpu, run.references, run.color)
    for name in over_time:
        if len(run.output_textures) < 2:
            result[name] = math.nan
        elif name == "temporal_instability":
            result[name] = run.instability_after(0)
        else:
            result[name] = metrics.get(name).numpy(run.references, run.color)
    return {name: result[name] for name in names}
