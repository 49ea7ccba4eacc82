"""The core of the methods: ``blur``, its dispatch plans and shutter ``steps``. Each method lives
in a module of its own beside this one (blurlab/methods/*.py) and registers a ``Method``
(registry.py) that carries everything other code needs: its parameters (params.py), instant
(docs/spec.md §1), backends, kind, default sweep grid and NumPy twin; its GPU passes run through
passes.py. This module also re-exports those names, the one import the method modules use.
docs/adding_a_method.md walks through adding one.
"""

from __future__ import annotations

import math
import warnings
import weakref
from dataclasses import dataclass, field
from numbers import Integral

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..core.gl import Texture, Timing
from ..core.references import accumulate
from ..core.render import check_shutter, instant_time
from ..scene.blur_scales import scaled_scene
from ..sizes import DEFAULT_SIZE
from . import layers, plans
from .params import (
    FLOAT32_MAX,
    PARAM_SCALE_MAX,
    SEED,
    SEED_MAX,
    Param,
    as_float32,
    is_auto,
)
from .passes import (
    Pass,
    PassRunner,
    choice_defines,
    frame_textures,
    pass_uniforms,
    run_pass,
    shader_beside,
    timed,
    timers,
)
from .registry import (
    KINDS,
    Method,
    check_param,
    key_item,
    method,
    method_instant,
    methods,
    register,
    resolve_params,
    twin_keywords,
)

__all__ = [
    "FLOAT32_MAX",
    "KINDS",
    "MAX_STEPS",
    "PARAM_SCALE_MAX",
    "SEED",
    "SEED_MAX",
    "BlurResult",
    "Method",
    "Param",
    "Pass",
    "PassRunner",
    "as_float32",
    "blur",
    "blur_steps",
    "check_param",
    "check_steps",
    "shader_beside",
    "choice_defines",
    "frame_textures",
    "method",
    "method_instant",
    "methods",
    "pass_uniforms",
    "register",
    "render_and_blur",
    "render_steps",
    "resolve_params",
    "run_pass",
    "step_shutters",
    "timed",
    "twin_keywords",
]


@dataclass
class BlurResult:
    """What a method produced: the blurred color (downloaded on first access), the pass
    timings, and the intermediate buffers (e.g. TileMax and NeighborMax)."""

    method: str
    params: dict
    backend: str
    timings: dict[str, Timing]
    textures: dict[str, Texture] = field(repr=False)
    # The parameters given as "auto" and the values their rules chose (also in `params`).
    auto: dict = field(default_factory=dict)
    _arrays: dict = field(default_factory=dict, repr=False)

    @property
    def color(self) -> np.ndarray:
        return self._array("color")

    @property
    def buffers(self) -> dict[str, np.ndarray]:
        return {name: self._array(name) for name in self.textures if name != "color"}

    @property
    def total_ms(self) -> float:
        return sum(t.ms for t in self.timings.values())

    @property
    def clock(self) -> str:
        return next(iter(self.timings.values())).clock

    def _array(self, name: str) -> np.ndarray:
        if name not in self._arrays:
            self._arrays[name] = self.textures[name].download()
        return self._arrays[name]


def blur(
    ctx: Context,
    frame: Frame,
    name: str,
    backend: str | None = None,
    timed: bool = True,
    translucency: str = layers.TRANSLUCENCY.default,
    motion_coverage: float = layers.MOTION_COVERAGE.default,
    layer_filter: str = layers.LAYER_FILTER.default,
    **params,
) -> BlurResult:
    """Runs method `name` on `frame` (rendered, or built from your arrays) with `params`
    (unknown names are an error); returns a BlurResult. `timed=False` skips the per-pass
    timers (their waits for the GPU), for sweeps that only want the error; an untimed call
    made a third time on the same frame with the same parameters replays a plan recorded by
    the second (docs/spec.md §18), same bits at a fraction of the CPU cost.

    `translucency` ("composite", "composite_motion", "unblurred", "layered"), `motion_coverage`
    and `layer_filter` choose how a frame's translucent layer is blurred (docs/spec.md §20.4,
    blurlab.methods.layers); frames without one are blurred as they are, and so are frames given
    to methods that render their own sub-frames (accumulation, stochastic), which draw every
    sub-frame's translucent surfaces as the reference does."""
    if not isinstance(ctx, Context):
        raise TypeError(f"blurlab: blur needs a blurlab Context, not {type(ctx).__name__}")
    if not isinstance(frame, Frame):
        raise TypeError(f"blurlab: blur needs a blurlab Frame, not {type(frame).__name__}")
    options = layers.checked(
        name,
        translucency=translucency,
        motion_coverage=motion_coverage,
        layer_filter=layer_filter,
    )
    if frame.layered and options["translucency"] != "composite" and not method(name).renders:

        def blur_layer(layer: Frame, method_name: str) -> BlurResult:
            if method_name == name:  # the call's method, backend and parameters
                return blur(ctx, layer, name, backend, timed, **params)
            return blur(ctx, layer, method_name, timed=timed)

        return layers.blur_layers(ctx, frame, name, **options, blur=blur_layer)
    planned = not timed and plans.enabled()
    if planned:
        replayed = _replay(ctx, frame, name, backend, params)
        if replayed is not None:
            return replayed
    m = method(name)
    given_backend = backend
    backend = backend or m.backends[0]
    if backend not in m.backends:
        raise ValueError(f"blurlab: {name} runs on backends {m.backends}, not {backend!r}")
    values = resolve_params(m, frame, params)
    automatic = {key: values[key] for key, value in params.items() if is_auto(value)}
    warned = _check_instant(m, frame, values)
    plan_key = (
        None
        if not planned or warned or m.kind not in PLANNED_KINDS
        else _plan_key(name, given_backend, params)
    )
    if plan_key is not None and plan_key not in frame.plans:
        # A first sighting is only remembered: recording costs more than a call, and a sweep
        # makes most untimed calls once.
        if len(frame.plans) >= PLANS_PER_FRAME:
            frame.plans.clear()
        frame.plans[plan_key] = None
        plan_key = None
    recorder = plans.Recorder() if plan_key is not None else None
    inputs = frame_textures(ctx, frame)
    with timers(timed), plans.recording(recorder):
        outputs, timings = m.run(ctx, frame, inputs, values, backend)
    if recorder is not None:
        plan = plans.make_plan(ctx, recorder, inputs, outputs, values, backend)
        if plan is not None:
            frame.plans[plan_key] = plan
    result = BlurResult(name, values, backend, timings, outputs, automatic)
    weakref.finalize(result, ctx.recycle, *outputs.values())
    return result


# Kinds whose runs may be recorded and replayed (blurlab.methods.plans): their outputs depend
# on the frame's textures and the parameters alone.
PLANNED_KINDS = ("filter", "gather")
PLANS_PER_FRAME = 256  # keys seen and plans, per frame; beyond it all are dropped


def _plan_key(name: str, backend: str | None, given: dict) -> tuple | None:
    """The key of a call's plan: method, backend as given, and the given parameters in the
    order given, by type and value (as the validation cache keys them); None where a value is
    "auto" or not a plain number, bool or string."""
    key = [name, backend]
    for item in given.items():
        entry = key_item(*item)
        if entry is None:
            return None
        key.append(entry)
    return tuple(key)


def _replay(
    ctx: Context, frame: Frame, name: str, backend: str | None, given: dict
) -> BlurResult | None:
    """The BlurResult of replaying the plan recorded for this call, or None where none is (the
    call is new, unfit for a plan, or the frame's textures are no longer the recorded ones,
    e.g. uploaded to another context)."""
    if not frame.plans:
        return None
    key = _plan_key(name, backend, given)
    plan = frame.plans.get(key) if key is not None else None
    if plan is None or not plan.matches(ctx, frame.textures):
        return None
    outputs, timings = plan.run()
    result = BlurResult(name, dict(plan.values), plan.backend, timings, outputs)
    weakref.finalize(result, ctx.recycle, *outputs.values())
    return result


def _check_instant(m: Method, frame: Frame, values: dict) -> bool:
    """Warns when a rendered frame was not rendered at the instant the method expects; True
    when it warned."""
    if frame.time is None or frame.camera is None:
        return False
    expected = m.instant(values) if callable(m.instant) else m.instant
    if abs(instant_time(expected, frame.shutter) - frame.time) > 1e-12:
        warnings.warn(
            f"blurlab: {m.name} expects the G-buffer at the shutter's {expected} "
            f"(t = {instant_time(expected, frame.shutter)}), this frame is at t = {frame.time}; "
            f"render with instant=bl.method_instant({m.name!r}, params) or use bl.render_and_blur",
            stacklevel=3,
        )
        return True
    return False


def render_and_blur(
    ctx: Context,
    scene,
    name: str,
    size=DEFAULT_SIZE,
    shutter=None,
    backend: str | None = None,
    steps: int = 1,
    **params,
) -> tuple[Frame | list[Frame], BlurResult]:
    """Renders `scene` at the instant method `name` expects and runs it: (frame, result).

    `steps` = n > 1 splits the shutter into n equal sub-intervals, renders and blurs each over
    its own sub-interval and averages the n results (render_steps, blur_steps); the first
    element is then the list of the n frames. steps = 1 is the plain render and blur."""
    frames = render_steps(ctx, scene, name, steps, size, shutter, **params)
    result = blur_steps(ctx, frames, name, backend, **params)
    return (frames[0] if len(frames) == 1 else frames), result


MAX_STEPS = 256


def check_steps(name: str, steps) -> int:
    """`steps` as an int in 1..MAX_STEPS for a post-process method; raises naming both."""
    if isinstance(steps, bool) or not isinstance(steps, Integral):
        raise TypeError(f"blurlab: steps must be an integer, not {steps!r}")
    if not 1 <= steps <= MAX_STEPS:
        raise ValueError(f"blurlab: steps = {steps} is outside 1..{MAX_STEPS}")
    if steps > 1 and method(name).renders:
        raise ValueError(
            f"blurlab: steps applies to post-process methods; {name} renders its own sub-frames"
        )
    return int(steps)


def step_shutters(shutter: tuple[float, float], steps: int) -> list[tuple[float, float]]:
    """The n equal sub-intervals [t0 + i/n·Δ, t0 + (i+1)/n·Δ] of a shutter (Δ = t1 - t0)."""
    t0, t1 = shutter
    if steps == 1:
        return [(t0, t1)]
    edges = [t0 + (t1 - t0) * i / steps for i in range(steps)] + [t1]
    return list(zip(edges[:-1], edges[1:], strict=True))


def render_steps(
    ctx: Context, scene, name: str, steps: int = 1, size=DEFAULT_SIZE, shutter=None, **params
) -> list[Frame]:
    """The G-buffers that `blur_steps` needs: one per sub-interval of the shutter, each at the
    instant method `name` expects within it, its motion over the sub-interval."""
    steps = check_steps(name, steps)
    shutter = check_shutter(scene.shutter if shutter is None else shutter)
    method_params = {k: v for k, v in params.items() if k not in layers.LAYER_PARAMS}
    instant = method_instant(name, method_params)
    scene = scaled_scene(scene, shutter)  # every step pivots on the whole shutter's centre
    return [ctx.render(scene, size, sub, instant=instant) for sub in step_shutters(shutter, steps)]


def blur_steps(
    ctx: Context,
    frames: list[Frame],
    name: str,
    backend: str | None = None,
    timed: bool = True,
    **params,
) -> BlurResult:
    """Blurs each frame of `render_steps` over its own sub-interval and averages the results
    in float32 on the GPU (the accumulate pass, weight 1/n each). One frame: bl.blur itself,
    bit for bit. The timings sum each pass over the steps and add `steps_accumulate` and
    `extra_gbuffers` (the G-buffer passes of steps 2..n, beyond the one every post-process
    method needs); params gain "steps"."""
    frames = list(frames)
    if not frames or not all(isinstance(f, Frame) for f in frames):
        raise TypeError("blurlab: blur_steps needs a non-empty list of blurlab Frames")
    steps = check_steps(name, len(frames))
    if steps == 1:
        return blur(ctx, frames[0], name, backend, timed, **params)
    height, width = frames[0].shape
    if any(f.shape != (height, width) for f in frames):
        raise ValueError("blurlab: the frames of blur_steps differ in size")
    total = ctx.pooled((height, width, 4))
    total.clear()
    timings: dict[str, Timing] = {}
    chosen: list[dict] = []
    for frame in frames:
        result = blur(ctx, frame, name, backend, timed, **params)
        add = Timing(math.nan, "untimed")
        if timed:
            with ctx.timer() as add:
                accumulate(ctx, result.textures["color"], total, 1 / steps)
        else:
            accumulate(ctx, result.textures["color"], total, 1 / steps)
        for key, timing in {**result.timings, "steps_accumulate": add}.items():
            before = timings.get(key, Timing(0.0, timing.clock))
            timings[key] = Timing(before.ms + timing.ms, timing.clock)
        values, backend_used = result.params, result.backend
        chosen.append(result.auto)
        del result  # back to the pool before the next step
    extra = sum(f.timings["gbuffer"].ms for f in frames[1:] if "gbuffer" in f.timings)
    clock = next(iter(timings.values())).clock
    timings["extra_gbuffers"] = Timing(extra, clock)
    # "auto" chooses per step, each from its own sub-interval's motion: one value where they
    # agree, else the list.
    auto = {}
    for key in chosen[0]:
        per_step = [c[key] for c in chosen]
        auto[key] = per_step[0] if len(set(per_step)) == 1 else per_step
    params = {**values, **auto, "steps": steps}
    out = BlurResult(name, params, backend_used, timings, {"color": total}, auto)
    weakref.finalize(out, ctx.recycle, total)
    return out
