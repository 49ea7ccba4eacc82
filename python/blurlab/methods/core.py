"""Motion-blur methods by name: ``bl.methods()`` lists them, ``bl.blur(ctx, frame, name, ...)``
runs one. Each method declares the G-buffer instant it wants (SPEC.md §1), its parameters with
defaults, and its backends; its passes are C++ classes with a NumPy twin in bl.reference.
"""

from __future__ import annotations

import contextvars
import math
import warnings
import weakref
from collections.abc import Callable
from dataclasses import dataclass, field
from numbers import Integral, Real

import numpy as np

from . import _core
from .context import Context, Texture, Timing
from .frame import Frame


@dataclass
class BlurResult:
    """What a method produced: the blurred color (downloaded on first access), the pass
    timings, and the intermediate buffers (e.g. TileMax and NeighborMax)."""

    method: str
    params: dict
    backend: str
    timings: dict[str, Timing]
    textures: dict[str, Texture] = field(repr=False)
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

    def allowed(self) -> str:
        """What values are allowed, in words (for error messages and docs)."""
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


@dataclass(frozen=True)
class Method:
    name: str
    # "center" or "close": the G-buffer time the method expects, or a function of the params
    instant: str | Callable[[dict], str]
    params: dict[str, Param]
    backends: tuple[str, ...]
    # (ctx, frame, inputs: dict[str, Texture], params, backend) -> (outputs, timings)
    run: Callable
    doc: str = ""
    # True for methods that render sub-frames themselves (accumulation, stochastic): `steps`
    # does not apply to them.
    renders: bool = False


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
    timers (their waits for the GPU), for sweeps that only want the error."""
    if not isinstance(ctx, Context):
        raise TypeError(f"blurlab: blur needs a blurlab Context, not {type(ctx).__name__}")
    if not isinstance(frame, Frame):
        raise TypeError(f"blurlab: blur needs a blurlab Frame, not {type(frame).__name__}")
    m = method(name)
    backend = backend or m.backends[0]
    if backend not in m.backends:
        raise ValueError(f"blurlab: {name} runs on backends {m.backends}, not {backend!r}")
    values = resolve_params(m, frame, params)
    _check_instant(m, frame, values)
    token = _TIMED.set(timed)
    try:
        outputs, timings = m.run(ctx, frame, frame_textures(ctx, frame), values, backend)
    finally:
        _TIMED.reset(token)
    result = BlurResult(name, values, backend, timings, outputs)
    weakref.finalize(result, ctx._recycle, *outputs.values())
    return result


def _check_instant(m: Method, frame: Frame, values: dict) -> None:
    """Warns when a rendered frame was not rendered at the instant the method expects."""
    if frame.time is None or frame.camera is None:
        return
    from .render import instant_time

    expected = m.instant(values) if callable(m.instant) else m.instant
    if abs(instant_time(expected, frame.shutter) - frame.time) > 1e-12:
        warnings.warn(
            f"blurlab: {m.name} expects the G-buffer at the shutter's {expected} "
            f"(t = {instant_time(expected, frame.shutter)}), this frame is at t = {frame.time}; "
            f"render with instant=bl.methods_instant({m.name!r}, params) or use bl.render_and_blur",
            stacklevel=3,
        )


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
    from .render import check_shutter

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
    total = ctx._pooled((height, width, 4))
    total.clear()
    accumulate = ctx._pass("accumulate", _core.AccumulatePass)
    timings: dict[str, Timing] = {}
    for frame in frames:
        result = blur(ctx, frame, name, backend, timed, **params)
        add = Timing(math.nan, "untimed")
        if timed:
            with ctx.timer() as add:
                accumulate.run(result.textures["color"]._core, total._core, 1 / steps)
        else:
            accumulate.run(result.textures["color"]._core, total._core, 1 / steps)
        for key, timing in {**result.timings, "steps_accumulate": add}.items():
            before = timings.get(key, Timing(0.0, timing.clock))
            timings[key] = Timing(before.ms + timing.ms, timing.clock)
        values, backend_used = result.params, result.backend
        del result  # back to the pool before the next step
    extra = sum(f.timings["gbuffer"].ms for f in frames[1:] if "gbuffer" in f.timings)
    clock = next(iter(timings.values())).clock
    timings["extra_gbuffers"] = Timing(extra, clock)
    out = BlurResult(name, {**values, "steps": steps}, backend_used, timings, {"color": total})
    weakref.finalize(out, ctx._recycle, total)
    return out


def resolve_params(m: Method, frame: Frame | None, given: dict, frame_free: bool = False) -> dict:
    unknown = set(given) - set(m.params)
    if unknown:
        raise TypeError(
            f"blurlab: {m.name} has no parameter(s) {sorted(unknown)}; its parameters are "
            + ", ".join(f"{k} (default {_describe(p.default)})" for k, p in m.params.items())
        )
    values = {}
    for key, p in m.params.items():
        value = given.get(key, None)
        if value is None and callable(p.default) and frame_free:
            continue  # defaults read from a frame are not needed to know the instant
        if value is None:
            value = p.default(frame) if callable(p.default) else p.default
        if value is None:  # an optional parameter, such as trail's history
            values[key] = None
            continue
        values[key] = _typed(m.name, key, value, p)
    return values


def _describe(default) -> str:
    return "from the frame" if callable(default) else repr(default)


def check_param(name: str, key: str, value):
    """`value` as parameter `key` of method `name` takes it, or the error a blur would raise:
    for callers (sweeps) that check their values before running anything."""
    m = method(name)
    if key not in m.params:
        raise ValueError(f"blurlab: {name} has no parameter {key!r}")
    return _typed(name, key, value, m.params[key])


def _typed(method_name: str, key: str, value, p: Param):
    """`value` as parameter `key` of method `method_name` takes it (SPEC.md parameter tables):
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
    with np.errstate(over="ignore"):
        seen = float(np.float32(value)) if kind is float else value
    if kind is float and not math.isfinite(seen):
        raise ValueError(f"{where} = {_show(value)} overflows float32 ({p.allowed()})")
    too_low = p.low is not None and (seen <= p.low if p.low_open else seen < p.low)
    too_high = p.high is not None and seen > p.high
    if too_low or too_high:
        closed = p.low is not None and p.high is not None and not p.low_open
        verb = "is outside" if closed else "must be"
        raise ValueError(f"{where} = {_show(value)} {verb} {p.allowed()}")
    return value


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


def depth_range_soft_z(frame: Frame) -> float:
    """SPEC.md §3 default soft_z: 1 % of the frame's finite depth range."""
    if frame.depth_range is None:
        return 0.01
    near, far = frame.depth_range
    span = far - near
    return 0.01 * (span if span > 0 else max(abs(far), 1.0))


_TIMED: contextvars.ContextVar[bool] = contextvars.ContextVar("blurlab_timed", default=True)


def timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    """Runs one pass, timed by the context's clock unless blur(timed=False) asked otherwise
    (the Timing then says clock "untimed" and NaN ms)."""
    if not _TIMED.get():
        fn()
        timings[name] = Timing(math.nan, "untimed")
        return
    with ctx.timer() as timing:
        fn()
    timings[name] = timing


# --- reconstruct_mcguire2012 (SPEC.md §3) -------------------------------------------------


def _classify_params() -> dict:
    from .classify import classify_params

    return classify_params()


_FILTER_OPTIONS = ("jitter_tiles", "adaptive_samples", "early_exit")


def _mcguire_params(values: dict, params=None):
    p = params if params is not None else _core.McGuire2012Params()
    for key in ("k", "samples", "soft_z", "exposure"):
        setattr(p, key, values[key])
    p.seed = values["seed"]
    p.jitter_tiles = bool(values.get("jitter_tiles", 0))
    p.adaptive_samples = bool(values.get("adaptive_samples", 0))
    p.early_exit = values.get("early_exit", 0.0)
    p.validate()
    return p


def _guertin_params(values: dict):
    p = _core.Guertin2014Params()
    p.gamma, p.kappa = values["gamma"], values["kappa"]
    return _mcguire_params(values, p)


def _tile_passes(
    ctx: Context, motion, params, backend: str, diagonal_reach=False, with_bounds=False
):
    """TileMax (§3.2) and NeighborMax (§3.3, or the direction-keeping dilation of
    docs/guertin2014.md): (tiles, neighbors, timings, bounds). `with_bounds` has TileMax also
    write each tile's motion bounds for classification (docs/classify_and_steps.md)."""
    height, width = motion.shape[:2]
    grid = (-(-height // params.k), -(-width // params.k), 2)
    tiles, neighbors = ctx._pooled(grid), ctx._pooled(grid)
    tile_pass = ctx._pass("tile_max", _core.TileMaxPass)
    neighbor_pass = ctx._pass("neighbor_max", _core.NeighborMaxPass)
    timings: dict[str, Timing] = {}
    bounds = []
    if with_bounds:
        from .classify import tile_max_with_bounds

        run_tile_max = lambda: bounds.append(  # noqa: E731
            tile_max_with_bounds(ctx, tile_pass, motion, tiles, params)
        )
    else:
        run_tile_max = lambda: tile_pass.run(motion._core, tiles._core, params, backend)  # noqa: E731
    timed(ctx, timings, "tile_max", run_tile_max)
    timed(
        ctx,
        timings,
        "neighbor_max",
        lambda: neighbor_pass.run(tiles._core, neighbors._core, backend, diagonal_reach),
    )
    return tiles, neighbors, timings, (bounds[0] if bounds else None)


def _run_filter(name: str, pass_type, make_params, diagonal_reach: bool):
    """TileMax → NeighborMax → the reconstruct pass `name` (SPEC.md §3, docs/guertin2014.md),
    the last one tile class by tile class where the method offers classify=True."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        params = make_params(values)
        classified = values.get("classify", False)
        if classified:
            from . import classify

            classify.check_backend(values, backend, name)
            options = [o for o in _FILTER_OPTIONS if values.get(o)]
            if options:
                raise ValueError(
                    f"blurlab: {name} with classify=True takes none of the filter options "
                    f"yet; {', '.join(options)} set (docs/classify_and_steps.md)"
                )
        tiles, neighbors, timings, bounds = _tile_passes(
            ctx, inputs["motion"], params, backend, diagonal_reach, classified
        )
        result = ctx._pooled(inputs["color"].shape[:2] + (4,))
        reconstruct = ctx._pass(name, pass_type)

        def run_reconstruct():
            reconstruct.run(
                inputs["color"]._core,
                inputs["depth"]._core,
                inputs["motion"]._core,
                neighbors._core,
                result._core,
                params,
                backend,
            )

        extra = {}
        if classified:
            extra["tile_bounds"] = bounds
            extra.update(
                classify.run_classified(
                    ctx,
                    lambda pass_name, fn: timed(ctx, timings, pass_name, fn),
                    inputs,
                    neighbors,
                    bounds,
                    result,
                    params,
                    values["uniform_spread"],
                    reconstruct,
                    run_reconstruct,
                )
            )
        else:
            timed(ctx, timings, "reconstruct", run_reconstruct)
        return {"color": result, "tile_max": tiles, "neighbor_max": neighbors, **extra}, timings

    return run


SEED_MAX = 2**32 - 1
FLOAT32_MAX = float(np.finfo(np.float32).max)  # float parameters go to the GPU as float32
# Exposure and intensity scale motion, which the passes read as at most 2^20 px per component
# (shaders/common/inputs.glsl, docs/reliability.md); up to 1000 x that, tap positions stay
# below 2^31 px, where GLSL's float-to-int conversion is defined.
PARAM_SCALE_MAX = 1000.0
_K = Param(20, int, "tile size = largest blur radius, pixels (1..256)", 1, 256)
_SAMPLES = Param(15, int, "samples S per pixel (1..256)", 1, 256)
_SOFT_Z = Param(
    depth_range_soft_z, float, "soft depth extent, depth units (> 0)", 0, FLOAT32_MAX, True
)
_EXPOSURE = Param(1.0, float, "exposure E, fraction of the shutter (0..1000)", 0, PARAM_SCALE_MAX)

_FILTER_PARAMS = {
    "k": _K,
    "samples": _SAMPLES,
    "soft_z": _SOFT_Z,
    "exposure": _EXPOSURE,
    "seed": Param(0, int, "jitter seed (0..2^32-1)", 0, SEED_MAX),
    "jitter_tiles": Param(0, int, "1: jittered NeighborMax lookup against tile blockiness", 0, 1),
    "adaptive_samples": Param(0, int, "1: S scaled with the neighborhood's motion length", 0, 1),
    "early_exit": Param(0.0, float, "pixels whose neighborhood moves < this many px keep C", 0),
}

register(
    Method(
        name="reconstruct_mcguire2012",
        instant="center",
        params={**_FILTER_PARAMS, **_classify_params()},
        backends=("compute", "fragment"),
        run=_run_filter(
            "reconstruct_mcguire2012", _core.ReconstructMcGuire2012Pass, _mcguire_params, False
        ),
        doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
        "Blur (I3D 2012). SPEC.md §3; options in docs/guertin2014.md, classification in "
        "docs/classify_and_steps.md.",
    )
)


# --- reconstruct_guertin2014 (docs/guertin2014.md) -----------------------------------------

register(
    Method(
        name="reconstruct_guertin2014",
        instant="center",
        params={
            **_FILTER_PARAMS,
            "gamma": Param(
                1.5,
                float,
                "γ: px over 0.5 at which wc is V[X]'s direction (> 0)",
                0,
                FLOAT32_MAX,
                True,
            ),
            "kappa": Param(
                40.0, float, "κ: center weight S / (κ len(V[X])) (> 0)", 0, FLOAT32_MAX, True
            ),
        },
        backends=("compute", "fragment"),
        run=_run_filter(
            "reconstruct_guertin2014", _core.ReconstructGuertin2014Pass, _guertin_params, True
        ),
        doc="Guertin, McGuire, Nowrouzezahrai: A Fast and Stable Feature-Aware Motion Blur "
        "Filter (HPG 2014): SPEC.md §3 with direction-keeping dilation, two sampling "
        "directions, mirrored pairs and alignment weights. docs/guertin2014.md.",
    )
)


# --- reconstruct_urho3d (SPEC.md §3 variant, the seed's baseline) -------------------------


def default_far(frame: Frame) -> float:
    """The depth the Urho3D pass reads for +inf: the camera's far plane for rendered frames,
    else twice the largest finite depth."""
    if frame.camera is not None and "far" in frame.camera:
        return float(frame.camera["far"])
    if frame.depth_range is None or frame.depth_range[1] <= 0:
        return 1.0
    return min(2.0 * frame.depth_range[1], FLOAT32_MAX)  # finite even for depths near 3.4e38


def _run_urho3d(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    from .reference.urho3d import jitter_texture

    params = _mcguire_params(values)
    tiles, neighbors, timings, _ = _tile_passes(ctx, inputs["motion"], params, backend)
    result = ctx._pooled(inputs["color"].shape[:2] + (4,))
    key = ("urho3d_jitter", values["seed"])
    if key not in ctx._passes:
        ctx._passes[key] = ctx.upload(jitter_texture(values["seed"]))
    jitter = ctx._passes[key]
    reconstruct = ctx._pass("reconstruct_urho3d", _core.ReconstructUrho3dPass)
    timed(
        ctx,
        timings,
        "reconstruct",
        lambda: reconstruct.run(
            inputs["color"]._core,
            inputs["depth"]._core,
            inputs["motion"]._core,
            neighbors._core,
            jitter._core,
            result._core,
            params,
            values["far"],
        ),
    )
    return {"color": result, "tile_max": tiles, "neighbor_max": neighbors}, timings


register(
    Method(
        name="reconstruct_urho3d",
        instant="center",
        params={
            "k": _K,
            "samples": _SAMPLES,
            "soft_z": _SOFT_Z,
            "exposure": _EXPOSURE,
            "seed": Param(0, int, "seed of the 64 x 64 jitter texture (0..2^32-1)", 0, SEED_MAX),
            "far": Param(
                default_far, float, "depth that +inf is read as (> 0)", 0, FLOAT32_MAX, True
            ),
        },
        backends=("fragment",),
        run=_run_urho3d,
        doc="The reconstruct pass of the Urho3D thesis as printed there: a fragment pass, the "
        "seed's baseline. SPEC.md §3 variant; the shader's header lists the differences.",
    )
)


# --- the engines' gathers (SPEC.md §4) -----------------------------------------------------

EDGES = ("clamp", "ignore", "guard")


def _gather_params(values: dict) -> _core.GatherParams:
    p = _core.GatherParams()
    p.taps = values.get("taps", 10)
    p.intensity = values.get("intensity", 1.0)
    p.centered = values.get("direction", "backward") == "centered"
    p.edge = "clamp" if values["edge"] == "guard" else values["edge"]
    p.validate()
    return p


def _longest_motion(frame: Frame) -> float:
    speed = np.linalg.norm(frame.motion, axis=-1)
    speed = speed[np.isfinite(speed)]
    return float(speed.max()) if speed.size else 0.0


def _with_edge(ctx: Context, frame: Frame, inputs: dict, edge: str, reach: float, run):
    """Runs `run(inputs) -> (color texture, timings)` on the frame, or, for edge "guard", on
    the frame re-rendered with a margin wide enough for every tap, then crops the margin."""
    if edge != "guard":
        return run(inputs)
    if frame.scene is None or frame.time is None:
        raise ValueError(
            "blurlab: edge='guard' re-renders the frame with a margin, so it needs a frame "
            "made by ctx.render; use edge='clamp' or 'ignore' for frames built from arrays"
        )
    from .render import render_targets

    guard = math.ceil(reach * _longest_motion(frame)) + 2
    big, _, timing = render_targets(ctx, frame.scene, frame.size, frame.shutter, frame.time, guard)
    color, timings = run(big)
    height, width = frame.color.shape[:2]
    result = ctx._pooled((height, width, 4))
    result._core.copy_from(color._core, guard, guard)
    ctx._recycle(color, *big.values())
    return result, {"guard_gbuffer": timing, **timings}


def _run_gather(name: str, pass_type, reach: Callable[[dict], float]):
    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        params = _gather_params(values)
        gather = ctx._pass(name, pass_type)

        def on(textures):
            height, width = textures["color"].shape[:2]
            result = ctx._pooled((height, width, 4))
            timings: dict[str, Timing] = {}
            timed(
                ctx,
                timings,
                name,
                lambda: gather.run(
                    textures["color"]._core, textures["motion"]._core, result._core, params, backend
                ),
            )
            return result, timings

        color, timings = _with_edge(ctx, frame, inputs, values["edge"], reach(values), on)
        return {"color": color}, timings

    return run


_EDGE = Param(
    "clamp", EDGES, "taps outside the image: clamp, ignore, or guard (re-render a margin)"
)

register(
    Method(
        name="gather_weighted",
        instant="close",
        params={"edge": _EDGE},
        backends=("compute", "fragment"),
        run=_run_gather("gather_weighted", _core.GatherWeightedPass, lambda v: 1.5),
        doc="ogldev tutorial 41: taps along M/2 with weights 0.4/0.3/0.2/0.1. SPEC.md §4.",
    )
)

_BOX_PARAMS = {
    "taps": Param(10, int, "n equal taps (2..256)", 2, 256),
    "intensity": Param(
        1.0, float, "length of the blur, fraction of the motion (0..1000)", 0, PARAM_SCALE_MAX
    ),
    "direction": Param("backward", ("backward", "centered"), "taps behind X, or around it"),
    "edge": _EDGE,
}


def _box_reach(values: dict) -> float:
    return values["intensity"] * (0.5 if values["direction"] == "centered" else 1.0)


register(
    Method(
        name="gather_box",
        instant=lambda v: "center" if v.get("direction") == "centered" else "close",
        params=_BOX_PARAMS,
        backends=("compute", "fragment"),
        run=_run_gather("gather_box", _core.GatherBoxPass, _box_reach),
        doc='"Blurry things": n equal taps along the motion, backward or centered. SPEC.md §4.',
    )
)


def _camera_matrices(camera: dict) -> dict:
    """The uniforms of the camera-motion pass from a rendered frame's camera matrices."""
    return {
        "view_from_clip": np.linalg.inv(camera["projection"]).astype(np.float32),
        "world_from_view": np.linalg.inv(camera["view"][2]).astype(np.float32),
        "clip_from_world": camera["view_projection"][:2].astype(np.float32),
        "sky_from_clip": camera["sky_from_clip"].astype(np.float32),
        "sky_projection": camera["sky_projection"].astype(np.float32),
        "near": float(camera["near"]),
    }


def _run_camera_only(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    if frame.camera is None:
        raise ValueError(
            "blurlab: camera_only needs the camera's transforms: use a frame made by ctx.render"
        )
    params = _gather_params(values)
    camera_pass = ctx._pass("camera_motion", _core.CameraMotionPass)
    gather = ctx._pass("gather_box", _core.GatherBoxPass)

    def on(textures):
        height, width = textures["color"].shape[:2]
        guard = (width - frame.size[0]) // 2
        camera = frame.camera
        if guard:  # the margin's frustum, as render_targets widened it
            from .render import camera_matrices

            camera = camera_matrices(frame.scene, frame.size, tuple(camera["times"]), guard)
        matrices = _camera_matrices(camera)
        motion, result = ctx._pooled((height, width, 2)), ctx._pooled((height, width, 4))
        timings: dict[str, Timing] = {}
        timed(
            ctx,
            timings,
            "camera_motion",
            lambda: camera_pass.run(textures["depth"]._core, motion._core, matrices),
        )
        timed(
            ctx,
            timings,
            "gather_box",
            lambda: gather.run(
                textures["color"]._core, motion._core, result._core, params, backend
            ),
        )
        ctx._recycle(motion)
        return result, timings

    color, timings = _with_edge(ctx, frame, inputs, values["edge"], _box_reach(values), on)
    return {"color": color}, timings


register(
    Method(
        name="camera_only",
        instant=lambda v: "center" if v.get("direction") == "centered" else "close",
        params=_BOX_PARAMS,
        backends=("compute", "fragment"),
        run=_run_camera_only,
        doc="Urho3D thesis §2.3.2: motion from depth and the camera's transforms alone, then "
        "gather_box; moving objects get no blur of their own. SPEC.md §4.",
    )
)


# --- trail and accumulation (SPEC.md §4) ---------------------------------------------------


def _run_trail(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    alpha = values["alpha"]
    history = values["history"]
    if history is not None and not isinstance(history, BlurResult):
        raise TypeError("blurlab: trail history must be the previous frame's BlurResult or None")
    height, width = inputs["color"].shape[:2]
    result = ctx._pooled((height, width, 4))
    result.clear()
    accumulate = ctx._pass("accumulate", _core.AccumulatePass)

    def blend():
        if history is None:  # out_0 = C_0
            accumulate.run(inputs["color"]._core, result._core, 1.0)
            return
        if history.textures["color"].shape != (height, width, 4):
            raise ValueError("blurlab: trail history has another size than the frame")
        accumulate.run(inputs["color"]._core, result._core, alpha)
        accumulate.run(history.textures["color"]._core, result._core, 1.0 - alpha)

    timings: dict[str, Timing] = {}
    timed(ctx, timings, "trail", blend)
    return {"color": result}, timings


register(
    Method(
        name="trail",
        instant="close",
        params={
            "alpha": Param(0.5, float, "weight of the current frame, in [0, 1]", 0, 1),
            "history": Param(None, object, "the previous frame's BlurResult (None: first frame)"),
        },
        backends=("compute",),
        run=_run_trail,
        doc="Urho3D thesis §2.3.1: out_n = α·C_n + (1 - α)·out_{n-1}, feedback over a "
        "sequence. SPEC.md §4.",
    )
)


def _run_accumulation(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    if frame.scene is None:
        raise ValueError(
            "blurlab: accumulation renders the scene again: use a frame made by ctx.render"
        )
    reference = ctx.reference(
        frame.scene,
        frame.size,
        frame.shutter,
        samples=values["samples"],
        stratified=values["stratified"] == "stratified",
        seed=values["seed"],
        progress=False,
    )
    height, width = frame.color.shape[:2]
    result = ctx._pooled((height, width, 4))
    result._core.copy_from(reference.texture._core, 0, 0)
    timing = Timing(reference.ms_per_subframe * reference.samples, reference.clock)
    return {"color": result}, {"accumulation": timing}


register(
    Method(
        name="accumulation",
        instant="center",
        params={
            "samples": Param(8, int, "sub-frames N (1..4096; 4-32 shows the banding)", 1, 4096),
            "stratified": Param("uniform", ("uniform", "stratified"), "sub-frame times"),
            "seed": Param(0, int, "seed of stratified times (0..2^32-1)", 0, SEED_MAX),
        },
        backends=("compute",),
        run=_run_accumulation,
        renders=True,
        doc="Haeberli-Akeley accumulation (the OGRE paper): the reference with small N. "
        "SPEC.md §4.",
    )
)


# --- stochastic (SPEC.md §4, the OGRE paper) -----------------------------------------------


def _run_stochastic(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    from .reference.stochastic import ROTATED_GRID, slice_times
    from .render import render_targets

    slices, seed = values["slices"], values["seed"]
    if frame.scene is None:
        raise ValueError("blurlab: stochastic renders time slices: use a frame made by ctx.render")
    height, width = frame.color.shape[:2]
    result = ctx._pooled((height, width, 4))
    result.clear()
    combine = ctx._pass("stochastic", _core.StochasticPass)
    renders = combines = 0.0
    clock = ""
    for slice_index, t in enumerate(slice_times(frame.shutter, slices, seed)):
        for position, p in enumerate(ROTATED_GRID):
            jitter = (0.5 - p[0], 0.5 - p[1])
            targets, _, timing = render_targets(
                ctx, frame.scene, frame.size, frame.shutter, float(t), 0, jitter
            )
            with ctx.timer() as add:
                combine.run(
                    targets["color"]._core, result._core, slice_index, position, slices, seed
                )
            ctx._recycle(*targets.values())
            renders += timing.ms
            combines += add.ms
            clock = add.clock
    return {"color": result}, {
        "slice_renders": Timing(renders, clock),
        "stochastic": Timing(combines, clock),
    }


register(
    Method(
        name="stochastic",
        instant="center",
        params={
            "slices": Param(4, int, "time slices K (1..64); 4 K jittered renders", 1, 64),
            "seed": Param(
                0, int, "seed of slice times and per-pixel permutations (0..2^32-1)", 0, SEED_MAX
            ),
        },
        backends=("compute",),
        run=_run_stochastic,
        renders=True,
        doc="The OGRE paper's stochastic blur: K time slices, rotated-grid samples in and "
        "around each pixel, weights 5/32 and 3/32. SPEC.md §4.",
    )
)
