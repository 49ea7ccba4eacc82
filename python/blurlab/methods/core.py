"""The core of the methods: parameter declaration and validation, the registry, ``blur``,
shutter ``steps`` and pass timing. Each method lives in a module of its own beside this one
(blurlab/methods/*.py) and registers a ``Method`` that carries everything other code needs:
its parameters, instant (docs/spec.md §1), backends, kind, default sweep grid and NumPy twin.
docs/adding_a_method.md walks through adding one.
"""

from __future__ import annotations

import contextvars
import inspect
import math
import struct
import warnings
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np

from ..context import Context, Texture, Timing
from ..converged import accumulate
from ..frame import Frame
from ..render import check_shutter, instant_time
from . import plans


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


@dataclass(frozen=True)
class Param:
    """One parameter of a method: its default, its type and, for numbers, its allowed range.

    Every value passes through ``_typed`` before a method runs, so a method never sees a value
    of the wrong type or outside [low, high]: the error names the method, the parameter, the
    value and what is allowed.
    """

    default: object  # a value, or a callable(frame) -> value
    kind: object  # int, float, bool, a tuple of allowed strings, or object (anything)
    doc: str
    low: float | None = None  # inclusive bounds for int and float parameters
    high: float | None = None
    low_open: bool = False  # True: the value must be > low (e.g. soft_z > 0)
    # The rule that `"auto"` stands for: auto(frame, values) -> a value, where `values` holds
    # the call's other parameters (so a rule may read, say, the exposure); None: no "auto".
    auto: Callable | None = None

    def allowed(self) -> str:
        """What values are allowed, in words (for error messages and docs)."""
        values = self._allowed_values()
        return values + ', or "auto"' if self.auto is not None else values

    def _allowed_values(self) -> str:
        if isinstance(self.kind, tuple):
            return "one of " + ", ".join(repr(k) for k in self.kind)
        if self.kind is bool:
            return "True or False"
        if self.kind is object:
            return "any value"
        if self.low is not None and self.high is not None and not self.low_open:
            if self.kind is int:
                return f"{_num(self.low)}..{_num(self.high)}"
            return f"[{_num(self.low)}, {_num(self.high)}]"
        bounds = []
        if self.low is not None:
            bounds.append(f"{'>' if self.low_open else '>='} {_num(self.low)}")
        if self.high is not None:
            bounds.append(f"<= {_num(self.high)}")
        return "finite" + "".join(" and " + b for b in bounds) if bounds else "finite"


def _num(x: float) -> str:
    if float(x).is_integer() and abs(x) >= 2**16:
        exponent = math.log2(abs(x) + (1 if x < 0 else 0))
        if exponent.is_integer():
            return f"2^{int(exponent)}" if x > 0 else f"-2^{int(exponent)}"
        if math.log2(x + 1).is_integer():
            return f"2^{int(math.log2(x + 1))}-1"
    return f"{x:g}"


# What a method is, for the studies that choose methods by what they do:
#   filter    - a tile-based reconstruction filter (k, samples, soft_z): failure-suite
#               sensitivity to k and soft_z applies;
#   gather    - a post-process gather along the motion;
#   render    - renders sub-frames itself (accumulation, stochastic): `steps` does not apply,
#               and its output is not a convex combination of one frame's colors;
#   sequence  - blends a sequence of frames (trail): not swept over a single shutter.
KINDS = ("filter", "gather", "render", "sequence")


@dataclass(frozen=True)
class Method:
    """A registered method: everything the rest of blurlab needs to know about it."""

    name: str
    kind: str  # one of KINDS
    # "center" or "close": the G-buffer time the method expects, or a function of the params
    instant: str | Callable[[dict], str]
    params: dict[str, Param]
    backends: tuple[str, ...]
    # (ctx, frame, inputs: dict[str, Texture], params, backend) -> (outputs, timings)
    run: Callable
    doc: str = ""
    # The grid `blurlab study` and `bl.sweep` use by default: {param: [values]} or a list of
    # them (their union); {} is the defaults alone.
    default_grid: dict | list = field(default_factory=dict)
    # The NumPy twin: twin(*frame arrays named by twin_inputs, **params) -> (H, W, C) color,
    # keyword-only parameters named as in `params`, with no defaults of their own.
    twin: Callable | None = None
    twin_inputs: tuple[str, ...] = ("color", "depth", "motion")
    # Parameters whose time/error curves the study report draws (the thesis's tables 5.2/5.3).
    study_curves: tuple[str, ...] = ()
    # Shown in the failure suite's image gallery (one or two methods of each kind).
    gallery: bool = False
    # For a "render" method: the parameters under which it makes n renders, so that studies
    # compare such methods at equal cost (the per-object table of blurlab.studies.objects).
    renders_for: Callable[[int], dict] | None = None

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"blurlab: method kind {self.kind!r} is not one of {KINDS}")

    @property
    def renders(self) -> bool:
        """True for methods that render sub-frames themselves: `steps` does not apply."""
        return self.kind == "render"

    @property
    def sweepable(self) -> bool:
        """True for methods a single-shutter sweep can evaluate."""
        return self.kind != "sequence"

    def defaults(self, frame: Frame | None = None, **given) -> dict:
        """Every parameter's value for a call with `given` on `frame`, validated as blur
        validates them (defaults read from the frame need a frame)."""
        return resolve_params(self, frame, given)

    def twin_output(self, frame: Frame, **given) -> np.ndarray:
        """The NumPy twin's output for `frame` with `given` parameters (the rest at their
        defaults): what the GPU passes must match."""
        if self.twin is None:
            raise ValueError(f"blurlab: {self.name} has no NumPy twin of a single frame")
        values = resolve_params(self, frame, given)
        taken = twin_keywords(self.twin)
        arrays = [getattr(frame, name) for name in self.twin_inputs]
        return self.twin(
            *arrays, **{k: v for k, v in values.items() if taken is None or k in taken}
        )


def twin_keywords(twin: Callable) -> set[str] | None:
    """The method parameters a NumPy twin takes: its keyword-only parameters without a default
    (None where it takes **keywords, i.e. all of them). Keyword-only parameters with a default
    are extra inputs, such as a precomputed NeighborMax, not method parameters."""
    taken = set()
    for p in inspect.signature(twin).parameters.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            return None
        if p.kind is inspect.Parameter.KEYWORD_ONLY and p.default is inspect.Parameter.empty:
            taken.add(p.name)
    return taken


_REGISTRY: dict[str, Method] = {}


def register(method: Method) -> Method:
    _REGISTRY[method.name] = method
    return method


def methods() -> list[str]:
    """Names of the registered methods."""
    return list(_REGISTRY)


def method_instant(name: str, params: dict | None = None) -> str:
    """The G-buffer instant method `name` expects with `params` ("center" or "close")."""
    m = method(name)
    if callable(m.instant):
        return m.instant(resolve_params(m, None, params or {}, frame_free=True))
    return m.instant


def method(name: str) -> Method:
    if name not in _REGISTRY:
        raise ValueError(f"blurlab: no method {name!r}; registered methods: {methods()}")
    return _REGISTRY[name]


def blur(
    ctx: Context, frame: Frame, name: str, backend: str | None = None, timed: bool = True, **params
) -> BlurResult:
    """Runs method `name` on `frame` (rendered, or built from your arrays) with `params`
    (unknown names are an error); returns a BlurResult. `timed=False` skips the per-pass
    timers (their waits for the GPU), for sweeps that only want the error; an untimed call
    made a third time on the same frame with the same parameters replays a plan recorded by
    the second (docs/spec.md §18), same bits at a fraction of the CPU cost."""
    if not isinstance(ctx, Context):
        raise TypeError(f"blurlab: blur needs a blurlab Context, not {type(ctx).__name__}")
    if not isinstance(frame, Frame):
        raise TypeError(f"blurlab: blur needs a blurlab Frame, not {type(frame).__name__}")
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
    automatic = {key: values[key] for key, value in params.items() if _is_auto(value)}
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
    token = _TIMED.set(timed)
    try:
        with plans.recording(recorder):
            outputs, timings = m.run(ctx, frame, inputs, values, backend)
    finally:
        _TIMED.reset(token)
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
        entry = _key_item(*item)
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
    size=(640, 360),
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
    ctx: Context, scene, name: str, steps: int = 1, size=(640, 360), shutter=None, **params
) -> list[Frame]:
    """The G-buffers that `blur_steps` needs: one per sub-interval of the shutter, each at the
    instant method `name` expects within it, its motion over the sub-interval."""
    steps = check_steps(name, steps)
    shutter = check_shutter(scene.shutter if shutter is None else shutter)
    instant = method_instant(name, params)
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
    height, width = frames[0].color.shape[:2]
    if any(f.color.shape[:2] != (height, width) for f in frames):
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


# Validated values of the parameter sets already seen, per method: sweeps and benchmarks call
# blur with the same few sets thousands of times. The key holds the given values and the
# defaults read from the frame (soft_z), all of the plain types below ("auto" is never cached,
# it reads the frame's motion); the cache is bounded.
_RESOLVED: dict[int, tuple[Method, dict]] = {}
_RESOLVED_MAX = 4096
_CACHEABLE_TYPES = (int, float, bool, str)


def _key_item(name: str, value) -> tuple | None:
    """(name, type, value) that tells 1, 1.0, True and -0.0 apart; None for other types."""
    kind = type(value)
    if kind not in _CACHEABLE_TYPES or _is_auto(value):
        return None
    return (name, kind.__name__, value.hex() if kind is float else value)


def _resolved_key(m: Method, frame: Frame | None, given: dict) -> tuple | None:
    key = []
    for name, value in given.items():
        key.append(_key_item(name, value))
    for name, p in m.params.items():
        if name not in given and callable(p.default):
            key.append(_key_item(name, p.default(frame)))
    return None if None in key else tuple(sorted(key))


def resolve_params(m: Method, frame: Frame | None, given: dict, frame_free: bool = False) -> dict:
    """The validated values of every parameter of `m` from `given` and the defaults (reading
    `frame` where a default or an "auto" rule needs it)."""
    key = None if frame_free else _resolved_key(m, frame, given)
    if key is None:
        return _resolve_params(m, frame, given, frame_free)
    entry = _RESOLVED.get(id(m))
    if entry is None or entry[0] is not m:
        entry = _RESOLVED[id(m)] = (m, {})
    seen = entry[1]
    if key not in seen:
        values = _resolve_params(m, frame, given, frame_free)
        if len(seen) >= _RESOLVED_MAX:
            seen.clear()
        seen[key] = values
    return dict(seen[key])


def _resolve_params(m: Method, frame: Frame | None, given: dict, frame_free: bool) -> dict:
    unknown = set(given) - set(m.params)
    if unknown:
        raise TypeError(
            f"blurlab: {m.name} has no parameter(s) {sorted(unknown)}; its parameters are "
            + ", ".join(f"{k} (default {_describe(p.default)})" for k, p in m.params.items())
        )
    values = {}
    automatic = [key for key, value in given.items() if _is_auto(value)]
    for key, p in m.params.items():
        value = given.get(key, None)
        if key in automatic:
            if p.auto is None:
                raise ValueError(f"blurlab: {m.name} parameter {key} has no 'auto' rule")
            continue  # chosen below, once the other parameters are known
        if value is None and callable(p.default) and frame_free:
            continue  # defaults read from a frame are not needed to know the instant
        if value is None:
            value = p.default(frame) if callable(p.default) else p.default
        if value is None:  # an optional parameter, such as trail's history
            values[key] = None
            continue
        values[key] = _typed(m.name, key, value, p)
    if frame_free:
        return values
    for key in [key for key in m.params if key in automatic]:  # in declaration order
        if frame is None:
            raise ValueError(f"blurlab: {m.name} parameter {key}='auto' reads a frame")
        values[key] = _typed(m.name, key, m.params[key].auto(frame, values), m.params[key])
    return {key: values[key] for key in m.params if key in values}


def _is_auto(value) -> bool:
    return isinstance(value, str) and value == "auto"


def _describe(default) -> str:
    return "from the frame" if callable(default) else repr(default)


def check_param(name: str, key: str, value):
    """`value` as parameter `key` of method `name` takes it, or the error a blur would raise:
    for callers (sweeps) that check their values before running anything."""
    m = method(name)
    if key not in m.params:
        raise ValueError(f"blurlab: {name} has no parameter {key!r}")
    if _is_auto(value) and m.params[key].auto is not None:
        return value  # chosen per frame when the method runs
    return _typed(name, key, value, m.params[key])


def _typed(method_name: str, key: str, value, p: Param):
    """`value` as parameter `key` of method `method_name` takes it (parameter declarations):
    the one place where every method's parameters are type- and range-checked. Every error
    names the method, the parameter, the value and what is allowed."""
    where = f"blurlab: {method_name} parameter {key}"
    kind = p.kind
    if kind is object:
        return value
    if kind is bool:
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{where} must be True or False, not {_show(value)}")
        return bool(value)
    if isinstance(kind, tuple):
        # Compare strings only: `value in kind` on an array or other odd object may itself raise.
        if not isinstance(value, str) or value not in kind:
            raise ValueError(f"{where} must be {p.allowed()}, not {_show(value)}")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, Integral):
            raise TypeError(f"{where} must be an integer ({p.allowed()}), not {_show(value)}")
        value = int(value)
    else:
        if isinstance(value, bool) or not isinstance(value, Real):
            raise TypeError(f"{where} must be a number ({p.allowed()}), not {_show(value)}")
        try:
            value = float(value)
        except OverflowError:  # an int beyond float's range
            value = math.inf
        if not math.isfinite(value):
            raise ValueError(f"{where} must be finite ({p.allowed()}), not {_show(value)}")
    # The GPU gets float32: check the value it will see (1e-50 is 0 there, 1e39 is inf).
    seen = as_float32(value) if kind is float else value
    if kind is float and not math.isfinite(seen):
        raise ValueError(f"{where} = {_show(value)} overflows float32 ({p.allowed()})")
    too_low = p.low is not None and (seen <= p.low if p.low_open else seen < p.low)
    too_high = p.high is not None and seen > p.high
    if too_low or too_high:
        closed = p.low is not None and p.high is not None and not p.low_open
        verb = "is outside" if closed else "must be"
        raise ValueError(f"{where} = {_show(value)} {verb} {p.allowed()}")
    return value


_FLOAT32 = struct.Struct("f")


def as_float32(value: float) -> float:
    """`value` rounded to float32 as the GPU receives it; ±inf where it overflows."""
    try:
        return _FLOAT32.unpack(_FLOAT32.pack(value))[0]
    except OverflowError:
        return math.copysign(math.inf, value)


def _show(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def frame_textures(ctx: Context, frame: Frame) -> dict[str, Texture]:
    """The frame's color, depth and motion as textures of `ctx`: the rendered ones where the
    frame came from this context, uploaded (once per frame) otherwise."""
    textures = frame.textures
    if not all(k in textures and textures[k].context is ctx for k in ("color", "depth", "motion")):
        textures = {
            "color": ctx.upload(frame.color),
            "depth": ctx.upload(frame.depth),
            "motion": ctx.upload(frame.motion),
        }
        frame.textures = textures
    return textures


@dataclass(frozen=True)
class Pass:
    """One GPU pass of a method: the shader it runs and the method parameters it takes as
    uniforms of the same names. Its inputs and outputs are the shader's own samplers and images
    (ShaderPass.reflect lists them); `name` keys its timing."""

    name: str
    shader: str  # under shaders/
    params: tuple[str, ...] = ()


def pass_uniforms(params: dict[str, Param], values: dict, names) -> dict:
    """The uniforms of the parameters `names` from validated `values`: the same names; a
    choice becomes its index among the declared choices (see choice_defines)."""
    uniforms = {}
    for key in names:
        kind = params[key].kind
        uniforms[key] = kind.index(values[key]) if isinstance(kind, tuple) else values[key]
    return uniforms


def choice_defines(params: dict[str, Param], names) -> dict[str, int]:
    """#defines that name each choice's index, KEY_CHOICE (EDGE_IGNORE = 1), so that a shader
    compares a choice uniform with a name derived from the one declaration."""
    defines = {}
    for key in names:
        kind = params[key].kind
        if isinstance(kind, tuple):
            for index, choice in enumerate(kind):
                defines[f"{key}_{choice}".upper()] = index
    return defines


def run_pass(
    ctx: Context,
    timings: dict,
    step: Pass,
    params: dict[str, Param],
    values: dict,
    inputs: dict[str, Texture],
    outputs: dict[str, Texture],
    backend: str = "compute",
    uniforms: dict | None = None,
    defines: dict | None = None,
    group_per_texel: bool = False,
) -> None:
    """Runs `step` with the method's validated `values` (and any pass-level `uniforms`), timed
    under step.name."""
    extra = tuple(sorted(defines.items())) if defines else ()

    def make():
        all_defines = {**choice_defines(params, step.params), **dict(extra)}
        return ctx.shader_pass(step.shader, all_defines)

    shader = ctx.cached(("run_pass", step, id(params), extra), make)
    all_uniforms = {**pass_uniforms(params, values, step.params), **(uniforms or {})}

    def run():
        shader.run(inputs, outputs, all_uniforms, backend, group_per_texel)

    recorder = plans.active_recorder()
    if recorder is not None:
        recorder.runs.append(
            plans.RecordedRun(shader, inputs, outputs, all_uniforms, backend, group_per_texel)
        )
        recorder.timing_names.append(step.name)
    _timed(ctx, timings, step.name, run)


_TIMED: contextvars.ContextVar[bool] = contextvars.ContextVar("blurlab_timed", default=True)


def timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    """Runs one pass, timed by the context's clock unless blur(timed=False) asked otherwise
    (the Timing then says clock "untimed" and NaN ms). GPU work run this way, outside run_pass,
    is not recorded: a method run that has any is never replayed (blurlab.methods.plans)."""
    recorder = plans.active_recorder()
    if recorder is not None:
        recorder.unfit()
    _timed(ctx, timings, name, fn)


def _timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    if not _TIMED.get():
        fn()
        timings[name] = Timing(math.nan, "untimed")
        return
    with ctx.timer() as timing:
        fn()
    timings[name] = timing


SEED_MAX = 2**32 - 1
FLOAT32_MAX = float(np.finfo(np.float32).max)  # float parameters go to the GPU as float32
# Exposure and intensity scale motion, which the passes read as at most 2^20 px per component
# (shaders/common/inputs.glsl, docs/reliability.md); up to 1000 x that, tap positions stay
# below 2^31 px, where GLSL's float-to-int conversion is defined.
PARAM_SCALE_MAX = 1000.0
# Every method with random choices (jitter, stochastic times) takes this one seed parameter.
SEED = Param(0, int, "seed of the method's random choices", 0, SEED_MAX)
