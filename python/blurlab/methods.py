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
    default: object  # a value, or a callable(frame) -> value
    kind: object  # int, float, or a tuple of allowed strings
    doc: str


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
    **params,
) -> tuple[Frame, BlurResult]:
    """Renders `scene` at the instant method `name` expects and runs it: (frame, result)."""
    frame = ctx.render(scene, size, shutter, instant=method_instant(name, params))
    return frame, blur(ctx, frame, name, backend, **params)


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
        values[key] = _typed(m.name, key, value, p.kind)
    return values


def _describe(default) -> str:
    return "from the frame" if callable(default) else repr(default)


def _typed(method_name: str, key: str, value, kind):
    if isinstance(kind, tuple):
        if value not in kind:
            raise ValueError(
                f"blurlab: {method_name} parameter {key} must be one of {kind}, not {value!r}"
            )
        return value
    if kind is object:
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, Integral):
            raise TypeError(
                f"blurlab: {method_name} parameter {key} must be an integer, not {value!r}"
            )
        return int(value)
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"blurlab: {method_name} parameter {key} must be a number, not {value!r}")
    if not math.isfinite(value):
        raise ValueError(f"blurlab: {method_name} parameter {key} must be finite, not {value!r}")
    return float(value)


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


_FILTER_OPTIONS = ("jitter_tiles", "adaptive_samples", "early_exit")


def _mcguire_params(values: dict, params=None):
    p = params if params is not None else _core.McGuire2012Params()
    for key in ("k", "samples", "soft_z", "exposure"):
        setattr(p, key, values[key])
    if not 0 <= values["seed"] < 2**32:
        raise ValueError(f"blurlab: seed = {values['seed']} is outside 0..2^32-1")
    p.seed = values["seed"]
    for key in ("jitter_tiles", "adaptive_samples"):
        if values.get(key, 0) not in (0, 1):
            raise ValueError(f"blurlab: {key} = {values[key]} must be 0 (off) or 1 (on)")
        setattr(p, key, bool(values.get(key, 0)))
    p.early_exit = values.get("early_exit", 0.0)
    p.validate()
    return p


def _guertin_params(values: dict):
    p = _core.Guertin2014Params()
    p.gamma, p.kappa = values["gamma"], values["kappa"]
    return _mcguire_params(values, p)


def _tile_passes(ctx: Context, motion, params, backend: str, diagonal_reach: bool = False):
    """TileMax (§3.2) and NeighborMax (§3.3, or the direction-keeping dilation of
    docs/guertin2014.md): (tiles, neighbors, timings)."""
    height, width = motion.shape[:2]
    grid = (-(-height // params.k), -(-width // params.k), 2)
    tiles, neighbors = ctx._pooled(grid), ctx._pooled(grid)
    tile_pass = ctx._pass("tile_max", _core.TileMaxPass)
    neighbor_pass = ctx._pass("neighbor_max", _core.NeighborMaxPass)
    timings: dict[str, Timing] = {}
    timed(
        ctx, timings, "tile_max", lambda: tile_pass.run(motion._core, tiles._core, params, backend)
    )
    timed(
        ctx,
        timings,
        "neighbor_max",
        lambda: neighbor_pass.run(tiles._core, neighbors._core, backend, diagonal_reach),
    )
    return tiles, neighbors, timings


def _run_filter(name: str, pass_type, make_params, diagonal_reach: bool):
    """TileMax → NeighborMax → the reconstruct pass `name` (SPEC.md §3, docs/guertin2014.md)."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        params = make_params(values)
        tiles, neighbors, timings = _tile_passes(
            ctx, inputs["motion"], params, backend, diagonal_reach
        )
        result = ctx._pooled(inputs["color"].shape[:2] + (4,))
        reconstruct = ctx._pass(name, pass_type)
        timed(
            ctx,
            timings,
            "reconstruct",
            lambda: reconstruct.run(
                inputs["color"]._core,
                inputs["depth"]._core,
                inputs["motion"]._core,
                neighbors._core,
                result._core,
                params,
                backend,
            ),
        )
        return {"color": result, "tile_max": tiles, "neighbor_max": neighbors}, timings

    return run


_FILTER_PARAMS = {
    "k": Param(20, int, "tile size = largest blur radius, pixels (1..256)"),
    "samples": Param(15, int, "samples S per pixel (1..256)"),
    "soft_z": Param(depth_range_soft_z, float, "soft depth extent, depth units (> 0)"),
    "exposure": Param(1.0, float, "exposure E, fraction of the shutter (>= 0)"),
    "seed": Param(0, int, "jitter seed (0..2^32-1)"),
    "jitter_tiles": Param(0, int, "1: jittered NeighborMax lookup against tile blockiness"),
    "adaptive_samples": Param(0, int, "1: S scaled with the neighborhood's motion length"),
    "early_exit": Param(0.0, float, "pixels whose neighborhood moves < this many px keep C"),
}

register(
    Method(
        name="reconstruct_mcguire2012",
        instant="center",
        params=_FILTER_PARAMS,
        backends=("compute", "fragment"),
        run=_run_filter(
            "reconstruct_mcguire2012", _core.ReconstructMcGuire2012Pass, _mcguire_params, False
        ),
        doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
        "Blur (I3D 2012). SPEC.md §3; options in docs/guertin2014.md.",
    )
)


# --- reconstruct_guertin2014 (docs/guertin2014.md) -----------------------------------------

register(
    Method(
        name="reconstruct_guertin2014",
        instant="center",
        params={
            **_FILTER_PARAMS,
            "gamma": Param(1.5, float, "γ: px over 0.5 at which wc is V[X]'s direction (> 0)"),
            "kappa": Param(40.0, float, "κ: center weight S / (κ len(V[X])) (> 0)"),
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
    return 2.0 * frame.depth_range[1]


def _run_urho3d(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    from .reference.urho3d import jitter_texture

    params = _mcguire_params(values)
    if not values["far"] > 0:
        raise ValueError(f"blurlab: far = {values['far']} must be > 0 (depth units)")
    tiles, neighbors, timings = _tile_passes(ctx, inputs["motion"], params, backend)
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
            "k": Param(20, int, "tile size = largest blur radius, pixels (1..256)"),
            "samples": Param(15, int, "samples S per pixel (1..256)"),
            "soft_z": Param(depth_range_soft_z, float, "soft depth extent, depth units (> 0)"),
            "exposure": Param(1.0, float, "exposure E, fraction of the shutter (>= 0)"),
            "seed": Param(0, int, "seed of the 64 x 64 jitter texture (0..2^32-1)"),
            "far": Param(default_far, float, "depth that +inf is read as (> 0)"),
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
    "taps": Param(10, int, "n equal taps (2..256)"),
    "intensity": Param(1.0, float, "length of the blur, fraction of the motion (>= 0)"),
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
    if not 0.0 <= alpha <= 1.0:
        raise ValueError(f"blurlab: trail alpha = {alpha} is outside [0, 1]")
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
            "alpha": Param(0.5, float, "weight of the current frame, in [0, 1]"),
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
            "samples": Param(8, int, "sub-frames N (>= 1; 4-32 shows the banding)"),
            "stratified": Param("uniform", ("uniform", "stratified"), "sub-frame times"),
            "seed": Param(0, int, "seed of stratified times"),
        },
        backends=("compute",),
        run=_run_accumulation,
        doc="Haeberli-Akeley accumulation (the OGRE paper): the reference with small N. "
        "SPEC.md §4.",
    )
)


# --- stochastic (SPEC.md §4, the OGRE paper) -----------------------------------------------


def _run_stochastic(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    from .reference.stochastic import ROTATED_GRID, slice_times
    from .render import render_targets

    slices, seed = values["slices"], values["seed"]
    if not 1 <= slices <= 64:
        raise ValueError(f"blurlab: slices K = {slices} is outside 1..64")
    if not 0 <= seed < 2**32:
        raise ValueError(f"blurlab: seed = {seed} is outside 0..2^32-1")
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
            "slices": Param(4, int, "time slices K (1..64); 4 K jittered renders"),
            "seed": Param(0, int, "seed of slice times and per-pixel permutations"),
        },
        backends=("compute",),
        run=_run_stochastic,
        doc="The OGRE paper's stochastic blur: K time slices, rotated-grid samples in and "
        "around each pixel, weights 5/32 and 3/32. SPEC.md §4.",
    )
)
