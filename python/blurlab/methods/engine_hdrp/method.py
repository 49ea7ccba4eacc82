"""engine_hdrp: the motion blur of Unity's High Definition Render Pipeline, written from the
algorithm of docs/spec.md §17.4 and from HDRP's public manual (the Motion Blur volume override),
not from Unity's sources (spec.md here). Four passes, beside this file: velocity setup with
the camera clamp modes, polar velocity and linear depth in B10G11R11 codes
(velocity_setup.glsl); per-tile min and max (tile_min_max.glsl); the 3 x 3 neighbourhood, or
the scatter variant, and the tile classes early-out / fast / slow (neighborhood.glsl), which
lists each tile under its class (docs/spec.md §9.3); the reconstruction, one pass per class
over its tile list (reconstruct.glsl). NumPy twin: twin.engine_hdrp. Parameters below, at the
engine's defaults.

What it leaves out: the real packed texture format (the codes are kept exactly in RGBA32F), the
engine's exact sample weights and sample placement, its fast-path test and tile jitter, which
the manual does not give (blurlab's choices are named in §17.4: §3.4's cones and cylinders on
the slow path, a `fast_ratio` test on the neighbourhood's lengths, no jitter), and the scatter's
atomics (a gather gives the same maxima).
"""

from __future__ import annotations

from ...twins.small_float import UF11_MANTISSA, largest_finite
from .. import tiles as tile_lists
from ..camera_motion import split_camera_uniforms
from ..core import FLOAT32_MAX, SEED, Param, Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..gathers import BOX_PARAMS
from . import twin

# Lengths are stored as unsigned 11-bit floats (§17.4): longer ones would all read as this.
LONGEST_STORED = largest_finite(UF11_MANTISSA)

PARAMS = {
    "samples": Param(8, int, "Sample Count: most taps per pixel (presets 4 / 8 / 12)", 2, 64),
    "intensity": BOX_PARAMS["intensity"],
    "maximum_velocity": Param(
        200.0, float, "Maximum Velocity: longest non-camera-clamped velocity, px", 0, LONGEST_STORED
    ),
    "minimum_velocity": Param(
        2.0, float, "Minimum Velocity: slower neighbourhoods keep C, px", 0, LONGEST_STORED
    ),
    "depth_comparison_extent": Param(
        1.0,
        float,
        "Depth Comparison Extent: soft depth extent, depth units",
        0,
        FLOAT32_MAX,
        low_open=True,
    ),
    "camera_motion_blur": Param(True, bool, "Camera Motion Blur: False leaves camera motion out"),
    "camera_clamp_mode": Param(
        "none",
        ("none", "rotation", "translation", "separate", "full"),
        "Camera Clamp Mode: which camera motion gets its own clamp",
    ),
    "rotation_clamp": Param(0.03, float, "camera rotation clamp, screen fraction", 0, 1),
    "translation_clamp": Param(0.05, float, "camera translation clamp, screen fraction", 0, 1),
    "motion_vector_clamp": Param(0.05, float, "full camera motion clamp, screen fraction", 0, 1),
    "scatter": Param(False, bool, "16 px tiles whose velocity scatters into the tiles it reaches"),
    "fast_ratio": Param(
        0.5, float, "fast path where the shortest neighbourhood velocity is >= this x longest", 0, 1
    ),
    "seed": SEED,
    "tile_dispatch": tile_lists.TILE_DISPATCH,
}
SETUP = Pass("velocity_setup", shader_beside(__file__, "velocity_setup.glsl"), twin.SETUP_PARAMS)
TILE_MIN_MAX = Pass("tile_min_max", shader_beside(__file__, "tile_min_max.glsl"))
NEIGHBORHOOD = Pass(
    "neighborhood",
    shader_beside(__file__, "neighborhood.glsl"),
    ("scatter", "minimum_velocity", "fast_ratio"),
)
RECONSTRUCT = Pass(
    "reconstruct",
    shader_beside(__file__, "reconstruct.glsl"),
    ("samples", "depth_comparison_extent", "seed"),
)


def run(ctx, frame, inputs: dict, values: dict, backend: str, passes: dict):
    """The method's passes (docs/spec.md §17.4). The neighbourhood pass lists each tile under
    its class, and the reconstruction runs once per class over that class's list by an
    indirect dispatch, as HDRP dispatches its tile classes; tile_dispatch="one" runs it as one
    pass over every pixel instead, each taking its tile's class: the same bits."""
    height, width = inputs["color"].shape[:2]
    tile = twin.tile_size(values["scatter"])
    runner = PassRunner(ctx, PARAMS, values)
    velocity = ctx.pooled((height, width, 4))
    camera = split_camera_uniforms(frame.camera)
    runner.run(
        SETUP,
        {"depth": inputs["depth"], "motion": inputs["motion"]},
        {"velocity": velocity},
        uniforms=camera,
    )
    grid = (-(-height // tile), -(-width // tile))
    tiles = ctx.pooled((*grid, 4))
    runner.run(TILE_MIN_MAX, {"velocity": velocity}, {"tiles": tiles}, uniforms={"tile": tile})
    neighborhood = ctx.pooled((*grid, 4))
    radius = twin.scatter_radius(tile, twin.reach_px((width, height), values), grid)
    lists = tile_lists.empty_lists(ctx, (height, width), tile, twin.CLASS_NAMES)
    runner.run(
        NEIGHBORHOOD,
        {"tiles": tiles},
        {"neighborhood": neighborhood, "tile_counts": lists.counts, "tile_lists": lists.lists},
        uniforms={"tile": tile, "radius": radius},
    )
    result = ctx.pooled((height, width, 4))
    textures = {"color": inputs["color"], "velocity": velocity, "neighborhood": neighborhood}
    if values["tile_dispatch"] == "lists" and backend == "compute":
        classes = range(len(twin.CLASS_NAMES))
        into, at_tile = {"result": result}, {"tile": tile}
        tile_lists.run_per_class(runner, RECONSTRUCT, lists, classes, textures, into, at_tile)
    else:
        runner.run(RECONSTRUCT, textures, {"result": result}, backend, uniforms={"tile": tile})
    ctx.recycle(lists.classes, lists.lists)
    outputs = {
        "color": result,
        "velocity": velocity,
        "tiles": tiles,
        "neighborhood": neighborhood,
        "tile_counts": lists.counts,
    }
    return outputs, runner.timings


METHOD = Declaration(
    name="engine_hdrp",
    kind="gather",
    order=13,
    params=PARAMS,
    passes=(SETUP, TILE_MIN_MAX, NEIGHBORHOOD, RECONSTRUCT),
    run=run,
    default_grid=[{"samples": [4, 8, 12]}, {"scatter": [True]}],
    twin=twin.engine_hdrp,
    doc="Unity HDRP's motion blur, from its described algorithm and manual: velocity polar "
    "with linear depth in B10G11R11 codes, camera clamp modes, 32 px min/max tiles (16 px "
    "scattered), 3 x 3 neighbourhood, early-out / fast / slow tile classes, each "
    "dispatched over its own tile list. docs/spec.md §17.4.",
    tile_lists=twin.CLASS_NAMES,
)
