"""Motion-blur methods by name: ``bl.methods()`` lists them, ``bl.blur(ctx, frame, name, ...)``
runs one. Each method declares the G-buffer instant it wants (SPEC.md §1), its parameters with
defaults, and its backends; its passes are C++ classes with a NumPy twin in bl.reference.
"""

from __future__ import annotations

import math
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
    kind: type  # int or float
    doc: str


@dataclass(frozen=True)
class Method:
    name: str
    instant: str  # "center" or "close": the G-buffer time the method expects
    params: dict[str, Param]
    backends: tuple[str, ...]
    run: Callable  # (ctx, inputs: dict[str, Texture], params: dict, backend) -> (outputs, timings)
    doc: str = ""


_REGISTRY: dict[str, Method] = {}


def register(method: Method) -> Method:
    _REGISTRY[method.name] = method
    return method


def methods() -> list[str]:
    """Names of the registered methods."""
    return list(_REGISTRY)


def method(name: str) -> Method:
    if name not in _REGISTRY:
        raise ValueError(f"blurlab: no method {name!r}; registered methods: {methods()}")
    return _REGISTRY[name]


def blur(ctx: Context, frame: Frame, name: str, backend: str | None = None, **params) -> BlurResult:
    """Runs method `name` on `frame` (rendered, or built from your arrays) with `params`
    (unknown names are an error); returns a BlurResult."""
    if not isinstance(ctx, Context):
        raise TypeError(f"blurlab: blur needs a blurlab Context, not {type(ctx).__name__}")
    if not isinstance(frame, Frame):
        raise TypeError(f"blurlab: blur needs a blurlab Frame, not {type(frame).__name__}")
    m = method(name)
    backend = backend or m.backends[0]
    if backend not in m.backends:
        raise ValueError(f"blurlab: {name} runs on backends {m.backends}, not {backend!r}")
    values = resolve_params(m, frame, params)
    outputs, timings = m.run(ctx, frame_textures(ctx, frame), values, backend)
    result = BlurResult(name, values, backend, timings, outputs)
    weakref.finalize(result, ctx._recycle, *outputs.values())
    return result


def resolve_params(m: Method, frame: Frame, given: dict) -> dict:
    unknown = set(given) - set(m.params)
    if unknown:
        raise TypeError(
            f"blurlab: {m.name} has no parameter(s) {sorted(unknown)}; its parameters are "
            + ", ".join(f"{k} (default {_describe(p.default)})" for k, p in m.params.items())
        )
    values = {}
    for key, p in m.params.items():
        value = given.get(key, None)
        if value is None:
            value = p.default(frame) if callable(p.default) else p.default
        values[key] = _typed(m.name, key, value, p.kind)
    return values


def _describe(default) -> str:
    return "from the frame" if callable(default) else repr(default)


def _typed(method_name: str, key: str, value, kind: type):
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
    finite = frame.depth[np.isfinite(frame.depth)]
    if finite.size == 0:
        return 0.01
    span = float(finite.max() - finite.min())
    return 0.01 * (span if span > 0 else max(float(abs(finite.max())), 1.0))


def timed(ctx: Context, timings: dict, name: str, fn: Callable) -> None:
    with ctx.timer() as timing:
        fn()
    timings[name] = timing


# --- reconstruct_mcguire2012 (SPEC.md §3) -------------------------------------------------


def _mcguire_params(values: dict) -> _core.McGuire2012Params:
    p = _core.McGuire2012Params()
    for key in ("k", "samples", "soft_z", "exposure"):
        setattr(p, key, values[key])
    if not 0 <= values["seed"] < 2**32:
        raise ValueError(f"blurlab: seed = {values['seed']} is outside 0..2^32-1")
    p.seed = values["seed"]
    p.validate()
    return p


def _run_mcguire2012(ctx: Context, inputs: dict, values: dict, backend: str):
    params = _mcguire_params(values)
    height, width = inputs["color"].shape[:2]
    k = params.k
    grid = (-(-height // k), -(-width // k), 2)
    tiles, neighbors = ctx._pooled(grid), ctx._pooled(grid)
    result = ctx._pooled((height, width, 4))
    timings: dict[str, Timing] = {}
    tile_pass = ctx._pass("tile_max", _core.TileMaxPass)
    neighbor_pass = ctx._pass("neighbor_max", _core.NeighborMaxPass)
    reconstruct = ctx._pass("reconstruct_mcguire2012", _core.ReconstructMcGuire2012Pass)
    timed(
        ctx,
        timings,
        "tile_max",
        lambda: tile_pass.run(inputs["motion"]._core, tiles._core, params, backend),
    )
    timed(
        ctx,
        timings,
        "neighbor_max",
        lambda: neighbor_pass.run(tiles._core, neighbors._core, backend),
    )
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


register(
    Method(
        name="reconstruct_mcguire2012",
        instant="center",
        params={
            "k": Param(20, int, "tile size = largest blur radius, pixels (1..256)"),
            "samples": Param(15, int, "samples S per pixel (1..256)"),
            "soft_z": Param(depth_range_soft_z, float, "soft depth extent, depth units (> 0)"),
            "exposure": Param(1.0, float, "exposure E, fraction of the shutter (>= 0)"),
            "seed": Param(0, int, "jitter seed (0..2^32-1)"),
        },
        backends=("compute", "fragment"),
        run=_run_mcguire2012,
        doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
        "Blur (I3D 2012). SPEC.md §3.",
    )
)


# --- reconstruct_urho3d (SPEC.md §3 variant, the seed's baseline) -------------------------


def default_far(frame: Frame) -> float:
    """The depth the Urho3D pass reads for +inf: the camera's far plane for rendered frames,
    else twice the largest finite depth."""
    if frame.camera is not None and "far" in frame.camera:
        return float(frame.camera["far"])
    finite = frame.depth[np.isfinite(frame.depth)]
    return 2.0 * float(finite.max()) if finite.size and finite.max() > 0 else 1.0


def _run_urho3d(ctx: Context, inputs: dict, values: dict, backend: str):
    from .reference.urho3d import jitter_texture

    params = _mcguire_params(values)
    if not values["far"] > 0:
        raise ValueError(f"blurlab: far = {values['far']} must be > 0 (depth units)")
    height, width = inputs["color"].shape[:2]
    k = params.k
    grid = (-(-height // k), -(-width // k), 2)
    tiles, neighbors = ctx._pooled(grid), ctx._pooled(grid)
    result = ctx._pooled((height, width, 4))
    key = ("urho3d_jitter", values["seed"])
    if key not in ctx._passes:
        ctx._passes[key] = ctx.upload(jitter_texture(values["seed"]))
    jitter = ctx._passes[key]
    timings: dict[str, Timing] = {}
    tile_pass = ctx._pass("tile_max", _core.TileMaxPass)
    neighbor_pass = ctx._pass("neighbor_max", _core.NeighborMaxPass)
    reconstruct = ctx._pass("reconstruct_urho3d", _core.ReconstructUrho3dPass)
    timed(
        ctx,
        timings,
        "tile_max",
        lambda: tile_pass.run(inputs["motion"]._core, tiles._core, params, backend),
    )
    timed(
        ctx,
        timings,
        "neighbor_max",
        lambda: neighbor_pass.run(tiles._core, neighbors._core, backend),
    )
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
