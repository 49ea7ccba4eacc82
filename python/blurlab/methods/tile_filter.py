"""The shared core of the tile-based reconstruction filters (docs/spec.md §3): their common
parameters, TileMax → NeighborMax, and the filter pipeline that ends in a method's own
reconstruct pass. reconstruct_mcguire2012, reconstruct_guertin2014 and reconstruct_urho3d (each a
folder beside this module) are built on it. With the option packed_inputs (mcguire2012 and
guertin2014) TileMax and
reconstruct read the half-float textures that packed_inputs() makes once per frame, and with
half_result the reconstruct writes half floats (docs/spec.md §19). TileMax's work-group layout
is one of TILE_MAX_VARIANTS, chosen for benchmarks by tile_max_variant().
"""

from __future__ import annotations

import math
import weakref

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from .core import FLOAT32_MAX, PARAM_SCALE_MAX, SEED, Param, Pass, PassRunner
from .params import WithdrawnAuto
from .variants import PassVariants


def depth_range_soft_z(frame: Frame) -> float:
    """docs/spec.md §3 default soft_z: 1 % of the frame's finite depth range."""
    if frame.depth_range is None:
        return 0.01
    near, far = frame.depth_range
    span = far - near
    return 0.01 * (span if span > 0 else max(abs(far), 1.0))


# The rules that k="auto" and samples="auto" stood for, withdrawn (docs/spec.md §14,
# docs/recommend.md): on random scenes that no fit had read they lost up to 6 dB to the
# defaults (the auto_holds benchmark, which keeps judging them). The blur radius the frame's
# motion asks for is a high percentile of |M|·E/2 over its moving pixels; the 95th leaves out
# the fastest 5 %, whose blur the neighbourhood dilation still spreads.
AUTO_PERCENTILE = 95
AUTO_K_STEP = 4  # k is rounded up to a multiple of 4 px (tile grids of whole work groups)
AUTO_K_SHARE = 1 / 8  # ... and capped at 1/8 of the image's shorter side (the engines' way)


def motion_radius(frame: Frame, exposure: float) -> float:
    """The AUTO_PERCENTILE-th percentile of |M|·E/2 over the pixels moving ≥ 1 px; 0 if none."""
    speeds = frame.moving_speeds
    if not speeds.size:
        return 0.0
    return float(np.percentile(speeds, AUTO_PERCENTILE)) * exposure / 2


def auto_k(frame: Frame, values: dict) -> int:
    """k from the frame's own motion: motion_radius rounded up to a multiple of AUTO_K_STEP,
    at least AUTO_K_STEP, at most AUTO_K_SHARE of the shorter image side (and 256), rounded
    down to a multiple of AUTO_K_STEP."""
    radius = motion_radius(frame, values["exposure"])
    share = min(256, int(min(frame.size) * AUTO_K_SHARE))
    cap = max(AUTO_K_STEP, AUTO_K_STEP * (share // AUTO_K_STEP))
    k = AUTO_K_STEP * math.ceil(radius / AUTO_K_STEP)
    return int(min(max(k, AUTO_K_STEP), cap))


def auto_samples(frame: Frame, values: dict) -> int:
    """S from the frame's own motion: about one sample per 2 px of the span 2·radius, odd (the
    middle sample is X itself), in 5..31."""
    radius = min(motion_radius(frame, values["exposure"]), values["k"])
    return int(min(max(2 * math.ceil(radius / 2) + 1, 5), 31))


# docs/spec.md §3's parameters, shared by every tile-based filter.
TILE_FILTER_PARAMS = {
    "k": Param(
        20,
        int,
        "tile size = largest blur radius, pixels",
        1,
        256,
        withdrawn_auto=WithdrawnAuto(
            auto_k,
            "Pass a fixed k, 1..256 (the default 20; a larger k for motion longer than 2k px), "
            "or let `blurlab recommend` choose k for your scenes.",
        ),
    ),
    "samples": Param(
        15,
        int,
        "samples S per pixel",
        1,
        256,
        withdrawn_auto=WithdrawnAuto(
            auto_samples,
            "Pass a fixed number of samples, 1..256 (the default 15; more for long motion, at "
            "more cost), or let `blurlab recommend` choose them for your scenes.",
        ),
    ),
    "soft_z": Param(
        depth_range_soft_z, float, "soft depth extent, depth units", 0, FLOAT32_MAX, low_open=True
    ),
    "exposure": Param(1.0, float, "exposure E, fraction of the shutter", 0, PARAM_SCALE_MAX),
    "seed": SEED,
}


# `far`, the depth that +inf is read as: a parameter of the filters that read depth as the Urho3D
# pass does (reconstruct_urho3d, and engine_unity's Z / far).
def default_far(frame: Frame) -> float:
    """The camera's far plane for rendered frames, else twice the largest finite depth."""
    if frame.camera is not None and "far" in frame.camera:
        return float(frame.camera["far"])
    if frame.depth_range is None or frame.depth_range[1] <= 0:
        return 1.0
    return min(2.0 * frame.depth_range[1], FLOAT32_MAX)  # finite even for depths near 3.4e38


FAR = Param(default_far, float, "depth that +inf is read as", 0, FLOAT32_MAX, low_open=True)
# The engines' refinements (docs/guertin2014.md "Options"), off by default so that docs/spec.md
# §3.4 holds; mcguire2012 and guertin2014 offer them.
FILTER_OPTIONS = {
    "jitter_tiles": Param(0, int, "1: jittered NeighborMax lookup against tile blockiness", 0, 1),
    "adaptive_samples": Param(0, int, "1: S scaled with the neighborhood's motion length", 0, 1),
    "early_exit": Param(
        0.0, float, "pixels whose neighborhood moves < this many px keep C", 0, FLOAT32_MAX
    ),
    "packed_inputs": Param(
        False, bool, "read colour, motion and depth as half floats packed once per frame"
    ),
    "half_result": Param(
        False, bool, "write the result as half floats (RGBA16F, an engine's HDR target)"
    ),
}
# Options that pick a shader variant (a #define), not a uniform of the same name. The two
# filter options were uniforms until the H100 showed that the jittered lookup's code, compiled
# in and switched off by a uniform, cost 15 % of the reconstruct pass (docs/benchmarks.md,
# "Where the filters' time goes"); as #defines each combination is a program of its own.
VARIANT_OPTIONS = ("packed_inputs", "half_result", "jitter_tiles", "adaptive_samples")


def uniform_names(params) -> tuple[str, ...]:
    """The parameters among `params` that a reconstruct pass takes as uniforms."""
    return tuple(key for key in params if key not in VARIANT_OPTIONS)


def variant_defines(values: dict) -> dict[str, int]:
    """The reconstruct pass's #defines for the VARIANT_OPTIONS among validated `values`
    (shaders/common/tile_filter.glsl)."""
    defines = {"JITTER_TILES": int(values["jitter_tiles"])}
    defines["ADAPTIVE_SAMPLES"] = int(values["adaptive_samples"])
    if values["packed_inputs"]:
        defines["PACKED_INPUTS"] = 1
    if values["half_result"]:
        defines["HALF_RESULT"] = 1  # common/pass_main.glsl
    return defines


# The sweep grid every filter shares: each option gets one point beside the default
# configuration instead of multiplying the k × S product.
OPTIONS_AT_DEFAULT = [
    {"k": [20], "samples": [15], "jitter_tiles": [1]},
    {"k": [20], "samples": [15], "adaptive_samples": [1]},
    {"k": [20], "samples": [15], "early_exit": [2.0]},
]


# TileMax (§3.2) and NeighborMax (§3.3). NeighborMax's `diagonal_reach` is the
# direction-keeping dilation of docs/guertin2014.md: a property of the filter, not a parameter.
TILE_MAX = Pass("tile_max", "passes/tile_max.glsl", ("k", "exposure"))
NEIGHBOR_MAX = Pass("neighbor_max", "passes/neighbor_max.glsl")


# The layouts of TileMax's work group per tile (shaders/passes/tile_max.glsl's header; docs/spec.md
# §3.2): the #defines of each. All give the same bits; `blurlab bench layouts` times them.
TILE_MAX_VARIANTS = {
    "strided_8x8": {},
    "strided_8x8_subgroup": {"TILE_MAX_SUBGROUP": 1},
    "rows_32": {"TILE_MAX_THREADS": 32},
    "rows_64": {"TILE_MAX_THREADS": 64},
    "rows_128": {"TILE_MAX_THREADS": 128},
    "rows_64_subgroup": {"TILE_MAX_THREADS": 64, "TILE_MAX_SUBGROUP": 1},
    "rows_128_subgroup": {"TILE_MAX_THREADS": 128, "TILE_MAX_SUBGROUP": 1},
}
# Fastest on the H100 at 1080p (speed_floor, 2026-11-24): 0.0200 ms at k = 20 and 0.0195 at
# k = 40, against 0.0235 and 0.0260 for strided_8x8 (docs/benchmarks.md). Without subgroup
# operations (llvmpipe) it reduces in shared memory.
DEFAULT_TILE_MAX_VARIANT = "rows_128_subgroup"
TILE_MAX_LAYOUT = PassVariants("TileMax", TILE_MAX_VARIANTS, DEFAULT_TILE_MAX_VARIANT)
# Inside `with tile_max_variant(name):` TileMax's work group per tile takes layout `name`.
tile_max_variant = TILE_MAX_LAYOUT.use


def largest_tile_for_one_thread(ctx: Context) -> int:
    """Largest tile side that one thread of TileMax scans. On a GPU a work group per tile pays
    off above 8 x 8 pixels; llvmpipe runs a group's threads as SIMD lanes and its barriers are
    costly, so there one thread per tile is faster up to 32 x 32 (docs/performance.md,
    docs/benchmarks.md)."""
    return 32 if ctx.software else 8


def tile_passes(
    passes: PassRunner, motion, backend: str, diagonal_reach=False, length_key_steps: int = 0
):
    """TileMax (§3.2) and NeighborMax (§3.3, or the direction-keeping dilation of
    docs/guertin2014.md), run by `passes`: (tiles, neighbors). With `length_key_steps` > 0 both
    compare lengths in steps of 1/length_key_steps px (shaders/common/length_key.glsl)."""
    ctx = passes.ctx
    height, width = motion.shape[:2]
    k = passes.values["k"]
    grid = (-(-height // k), -(-width // k), 2)
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    group_per_tile = k > largest_tile_for_one_thread(ctx)
    defines = {"LENGTH_KEY_STEPS": length_key_steps} if length_key_steps else {}
    if backend == "compute":
        defines["GROUP_PER_TILE"] = int(group_per_tile)  # common/group_pick.glsl
        if group_per_tile:
            defines.update(TILE_MAX_LAYOUT.defines())
    passes.run(
        TILE_MAX,
        {"motion": motion},
        {"tile_max": tiles},
        backend,
        defines=defines,
        group_per_texel=group_per_tile,
    )
    passes.run(
        NEIGHBOR_MAX,
        {"tile_max": tiles},
        {"neighbor_max": neighbors},
        backend,
        uniforms={"diagonal_reach": diagonal_reach},
        defines={"LENGTH_KEY_STEPS": length_key_steps} if length_key_steps else None,
    )
    return tiles, neighbors


PACK_INPUTS = "passes/pack_inputs.comp"


def packed_inputs(ctx: Context, frame: Frame, inputs: dict) -> dict:
    """docs/spec.md §19: the frame's colour and its motion + depth as two RGBA16F textures
    ({"color", "motion_depth"}), packed by the first call that asks and kept beside the frame's
    own textures in `inputs` (the frame's dict, frame_textures), so a sweep packs once per
    frame; the packing's time goes to frame.timings["pack_inputs"]. Not part of a recorded
    plan: a replay reads the kept textures."""
    if "packed_color" not in inputs:
        height, width = inputs["color"].shape[:2]
        color = ctx.empty((height, width, 4), "float16")
        motion_depth = ctx.empty((height, width, 4), "float16")
        sources = {name: inputs[name] for name in ("color", "depth", "motion")}
        with ctx.timer() as timing:
            ctx.shader_pass(PACK_INPUTS).run(
                sources, {"packed_color": color, "packed_motion_depth": motion_depth}
            )
        frame.timings["pack_inputs"] = timing
        inputs["packed_color"], inputs["packed_motion_depth"] = color, motion_depth
        weakref.finalize(frame, ctx.recycle, color, motion_depth)
    return {"color": inputs["packed_color"], "motion_depth": inputs["packed_motion_depth"]}


def run_filter(params: dict[str, Param], reconstruct: Pass, diagonal_reach: bool):
    """TileMax → NeighborMax → the method's `reconstruct` pass (docs/spec.md §3,
    docs/guertin2014.md); `params` are the method's parameter declarations. NeighborMax keeps a
    pass of its own: computing it in the reconstruct pass's prologue measured slower (§3.6).
    A Declaration's run: `passes` (the declared ones) hold `reconstruct` alone, run as given."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
        packed = values["packed_inputs"]
        if packed:
            textures = packed_inputs(ctx, frame, inputs)
            motion = textures["motion_depth"]  # TileMax reads its xy
        else:
            textures = {key: inputs[key] for key in ("color", "depth", "motion")}
            motion = inputs["motion"]
        runner = PassRunner(ctx, params, values)
        result_type = "float16" if values["half_result"] else "float32"
        defines = variant_defines(values)
        return reconstruct_on_tiles(
            runner,
            reconstruct,
            textures,
            motion,
            backend,
            diagonal_reach,
            result_type,
            defines=defines,
        )

    return run


def reconstruct_on_tiles(
    passes: PassRunner,
    reconstruct: Pass,
    textures: dict,
    motion,
    backend: str,
    diagonal_reach=False,
    dtype="float32",
    **options,
):
    """A tile filter's run after its inputs: TileMax and NeighborMax of `motion` (tile_passes),
    then `reconstruct` over `textures` and "neighbor_max" into a `dtype` result (`options` as
    PassRunner.run's). Returns the run's outputs and timings."""
    tiles, neighbors = tile_passes(passes, motion, backend, diagonal_reach)
    inputs = {**textures, "neighbor_max": neighbors}
    result = passes.run_result(reconstruct, inputs, backend, dtype, **options)
    return {"color": result, "tile_max": tiles, "neighbor_max": neighbors}, passes.timings


def options_filter(
    params: dict[str, Param], reconstruct: Pass, diagonal_reach: bool, grid: dict
) -> dict:
    """The Declaration fields of a filter that offers FILTER_OPTIONS (among its `params`):
    run_filter into its `reconstruct` pass on both backends, swept over `grid` and then each
    option on its own (OPTIONS_AT_DEFAULT)."""
    return {
        "kind": "filter",
        "params": params,
        "passes": (reconstruct,),
        "backends": ("compute", "fragment"),
        "run": run_filter(params, reconstruct, diagonal_reach),
        "default_grid": [grid, *OPTIONS_AT_DEFAULT],
    }
