"""gather_coverage: a post-process filter built from what measured best among the engines' and
the papers' filters (docs/spec.md §17.6): the two-sided motion and the dilation along each
tile's motion of engine_eevee, tile size and blur limit relative to the image height as
engine_unity's, taps along the neighbourhood's and X's own motion (Guertin 2014's two
directions, Unity's v_alt), and weights that estimate what share of each half-shutter a moving
pixel spends over X, with what lies behind X filling the rest. Passes: engine_eevee's tile
flatten and dilation at this method's tile size and limit (methods.eevee.dilated_tiles), the
dilation by scatter (keys cleared, the flatten offering each tile's reach by atomic max:
shaders/passes/reach_keys_clear.glsl, eevee_tile_flatten.glsl; §17.6), then
shaders/passes/coverage_gather.glsl, which resolves the keys itself unless
eevee.DILATION_LAYOUT says a pass of their own does (eevee_tile_resolve.glsl), then, where
film_filter > 0, shaders/passes/film_filter.glsl, unless film_through_taps reads the filter
through the gather's colour reads instead. The options of §17.6.1 (tap_spacing, early_exit,
uniform_tolerance, half_res_above) spend the gather's taps where the motion needs them;
half_res_above adds a pass of the same shader at half resolution before the gather
(gather_half). NumPy twin: blurlab.twins.coverage.gather_coverage; tap_plan below gives each
pixel's taps and path.
"""

from __future__ import annotations

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..twins import coverage as twin
from ..twins import film
from ..twins.eevee import EARLY_EXIT, resolve_reach_keys
from . import tiles as tile_lists
from .core import (
    SEED,
    BlurResult,
    Method,
    Param,
    Pass,
    PassRunner,
    method,
    register,
    resolve_params,
    twin_keywords,
)
from .eevee import dilated_tiles
from .tile_filter import TILE_FILTER_PARAMS
from .variants import PassVariants

PARAMS = {
    # 16 samples and 1.5 % tiles: the held-out rule of docs/recommend.md met the bar with them.
    "tile_percent": Param(
        1.5, float, "tile side, % of the image height (at least 8 px)", 0, 100, low_open=True
    ),
    "samples": Param(
        16, int, "taps on each half-shutter (half along the tile, half along X)", 2, 32
    ),
    "max_blur": Param(
        30.0, float, "longest half-motion, % of the image height", 0, 100, low_open=True
    ),
    "soft_z": TILE_FILTER_PARAMS["soft_z"],
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
    "film_filter": Param(
        0.0,
        float,
        "σ of a Gaussian film filter on the result, px (0: none, pixel-centre samples as the "
        "temporal reference; 0.5: Blender EEVEE's at its 1.5 px filter size)",
        0,
        4,
    ),
    "film_through_taps": Param(
        False,
        bool,
        "read the film filter through the gather's colour reads (each tap bilinear at a turning "
        "(±d, ±d) px, d the kernel's variance) instead of a pass after it; film_filter up to "
        f"{film.MAX_TAP_SIGMA:.2f}",
    ),
    # Just enough taps (§17.6.1): each off, or at today's value, by default.
    "tap_spacing": Param(
        0.0,
        float,
        "px of the tile's longer line per tap: a side takes clamp(ceil(longest / tap_spacing), "
        "2, samples) taps (0: samples everywhere)",
        0,
        1000,
    ),
    "early_exit": Param(
        EARLY_EXIT,
        float,
        "px: where the tile's longer line is shorter, X keeps its colour with no tap",
        0,
        1000,
    ),
    "uniform_tolerance": Param(
        0.0,
        float,
        "px: an X whose own trails lie this close to the tile's lines takes a plain gather of "
        "the taps moving as it does (0: off)",
        0,
        1000,
    ),
    "half_res_above": Param(
        0.0,
        float,
        "px: a 2 x 2 quad whose tile line and pixels' half-motions are all longer takes one "
        "gather, at its top-left pixel, in a pass at half resolution (0: off)",
        0,
        1000,
    ),
    "tile_dispatch": tile_lists.TILE_DISPATCH,
}
GATHER = Pass(
    "gather",
    "passes/coverage_gather.glsl",
    ("samples", "soft_z", "exposure", "seed", "early_exit"),
)
GATHER_HALF = Pass("gather_half", GATHER.shader, GATHER.params)
BLOCK_CLASSIFY = Pass("block_classify", GATHER.shader, ("early_exit",))
LIST_BLOCK = 16  # px: the blocks of the gather's lists (§17.6.2)
# The options whose passes compile in a path of their own only where they are on (> 0).
GATHER_OPTIONS = {
    "tap_spacing": "PER_TILE_SAMPLES",
    "uniform_tolerance": "UNIFORM_FAST_PATH",
    "half_res_above": "HALF_RES_READ",
}
# The gather's variants (shaders/passes/coverage_gather.glsl): every tap reads its colour, or
# only the taps that weigh on a sum do (fewer reads, a branch). Same bits; `blurlab bench layouts`
# --variants times both: on the H100 at 1080p fetch_all was as fast or faster (0.0628 against
# 0.0647 ms on teapot_pass, medians over 15 scenes 0.168 and 0.171, 2026-11-24), so it is the
# default, without the branch.
GATHER_VARIANTS = {"fetch_all": {}, "skip_unweighted": {"GATHER_SKIP_UNWEIGHTED": 1}}
GATHER_LAYOUT = PassVariants("gather", GATHER_VARIANTS, "fetch_all")
FILM = Pass("film", "passes/film_filter.glsl", ("film_filter",))
FILM_ROWS = Pass("film_rows", "passes/film_filter.glsl", ("film_filter",))
FILM_COLUMNS = Pass("film_columns", "passes/film_filter.glsl", ("film_filter",))
# The film filter's layouts (shaders/passes/film_filter.glsl): one pass of (2R + 1)² taps; two
# of 2R + 1 (rows, then columns) with an RGBA32F image between them; or one whose work group
# filters its rows in shared memory, then its columns there. Same kernel, sums in another
# order; `blurlab bench layouts` times them. On the H100 at 1080p, σ = 0.5, teapot_pass:
# 0.113 ms direct, 0.079 separable (two passes), 0.044 separable_shared (2026-11-24).
FILM_VARIANTS = {
    "direct": {},
    "separable": {"FILM_SEPARABLE": 1},
    "separable_shared": {"FILM_SHARED": 1},
}
FILM_LAYOUT = PassVariants("film filter", FILM_VARIANTS, "separable_shared")


def _film_filter(passes: PassRunner, gathered):
    """Step 4 of §17.6 on `gathered`, as FILM_LAYOUT says: the filtered texture."""
    ctx, values = passes.ctx, passes.values
    size = gathered.shape[:2]
    variant = FILM_LAYOUT.defines()
    defines = {**variant, "FILM_RADIUS": film.film_radius(values["film_filter"])}
    filtered = ctx.pooled((*size, 4))
    if "FILM_SEPARABLE" in variant:  # along rows into `rows`, then along its columns
        rows = ctx.pooled((*size, 4))
        steps = [(FILM_ROWS, gathered, rows, False), (FILM_COLUMNS, rows, filtered, True)]
    else:
        rows, steps = None, [(FILM, gathered, filtered, None)]
    for step, source, target, columns in steps:
        passes.run(
            step,
            {"color": source},
            {"result": target},
            uniforms={} if columns is None else {"film_columns": columns},
            defines=defines,
        )
    if rows is not None:
        ctx.recycle(rows)
    return filtered


def _gather_over_lists(passes: PassRunner, textures, gathered, uniforms, defines):
    """§17.6.2: the blocks sorted into still and moving lists, then the gather over each list
    into `gathered`; the lists."""
    ctx = passes.ctx
    lists = tile_lists.empty_lists(ctx, gathered.shape[:2], LIST_BLOCK, twin.BLOCK_CLASSES)
    tile_inputs = {k: t for k, t in textures.items() if k in ("color", "dilated", "tiles")}
    if "reach_keys" in textures:
        tile_inputs["reach_keys"] = textures["reach_keys"]
    passes.run(
        BLOCK_CLASSIFY,
        tile_inputs,
        {"block_class": lists.classes, "tile_counts": lists.counts, "tile_lists": lists.lists},
        uniforms={k: uniforms[k] for k in ("tile_size", "reach_limit")},
        defines={**defines, "BLOCK_CLASSIFY": 1},
    )
    classes = range(len(twin.BLOCK_CLASSES))
    into = {"result": gathered}
    tile_lists.run_per_class(passes, GATHER, lists, classes, textures, into, uniforms, defines)
    return lists


def run_coverage(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    """The method's passes (docs/spec.md §17.6). The gather runs over two lists of 16 px blocks,
    still (each pixel keeps its colour) and moving (§17.6.2), unless half_res_above is on or
    tile_dispatch is "one": then one pass covers every pixel, with the same bits."""
    size = inputs["color"].shape[:2]
    s = twin.tile_size(size[0], values["tile_percent"])
    reach_limit = twin.max_blur_px(size[0], values["max_blur"])
    passes = PassRunner(ctx, PARAMS, values)
    grids = dilated_tiles(
        ctx,
        frame,
        passes.timings,
        PARAMS,
        values,
        size,
        s,
        reach_limit,
        length_steps=twin.TILE_LENGTH_STEPS,
        jitter_reach=twin.JITTER_REACH,
    )
    gathered = ctx.pooled((*size, 4))
    textures = {"color": inputs["color"], "depth": inputs["depth"], "motion_sides": grids.sides}
    uniforms = {"tile_size": s, "reach_limit": reach_limit}
    defines = GATHER_LAYOUT.defines()
    if grids.keys is None:
        textures["dilated"] = grids.dilated
        tile_buffers = {"tiles": grids.tiles, "dilated": grids.dilated}
    else:  # the gather resolves the scatter dilation's keys itself
        textures.update(tiles=grids.tiles, reach_keys=grids.keys)
        tile_buffers = {"tiles": grids.tiles, "reach_keys": grids.keys}
        defines["GATHER_READS_KEYS"] = 1
    through_taps = values["film_through_taps"] and values["film_filter"] > 0
    if through_taps:
        if values["film_filter"] > film.MAX_TAP_SIGMA:
            raise ValueError(
                f"blurlab: gather_coverage film_through_taps reads the film filter as a 3-tap "
                f"kernel, which holds film_filter up to {film.MAX_TAP_SIGMA:.2f} px, not "
                f"{values['film_filter']}; use film_through_taps=False (a pass after the "
                "gather) for a wider filter"
            )
        defines = {**defines, "FILM_THROUGH_TAPS": 1}
        uniforms["film_spread"] = film.film_spread(values["film_filter"])
    for option, define in GATHER_OPTIONS.items():
        if values[option] > 0:
            defines[define] = 1
            uniforms[option] = values[option]
    if values["half_res_above"] > 0:  # the long quads' gathers first, at half resolution
        half = ctx.pooled(((size[0] + 1) // 2, (size[1] + 1) // 2, 4))
        half_defines = {**defines, "HALF_RES_GATHER": 1}
        del half_defines["HALF_RES_READ"]
        passes.run(GATHER_HALF, textures, {"result": half}, backend, uniforms, half_defines)
        textures["half_gathered"] = half
    lists = None
    on_lists = values["tile_dispatch"] == "lists" and values["half_res_above"] == 0
    if on_lists and backend == "compute":
        lists = _gather_over_lists(passes, textures, gathered, uniforms, defines)
    else:
        passes.run(GATHER, textures, {"result": gathered}, backend, uniforms, defines)
    if values["half_res_above"] > 0:
        ctx.recycle(half)
    outputs = {"color": gathered, **tile_buffers}
    if lists is not None:
        outputs.update(tile_counts=lists.counts, block_class=lists.classes)
        ctx.recycle(lists.lists)
    if values["film_filter"] > 0 and not through_taps:
        outputs.update(color=_film_filter(passes, gathered), unfiltered=gathered)
    return outputs, passes.timings


register(
    Method(
        name="gather_coverage",
        kind="gather",
        params=PARAMS,
        run=run_coverage,
        tile_lists=twin.BLOCK_CLASSES,
        default_grid={"samples": [4, 8, 16], "max_blur": [15.0, 30.0]},
        twin=twin.gather_coverage,
        translucent_layer=True,
        # film_through_taps reads film_filter as a 3-tap filter: up to 0.71 px (§17.6)
        linked_params=(("film_through_taps", "film_filter"),),
        doc="The engines' best parts combined: two-sided motion, dilation along each tile's "
        "motion, tiles and limit relative to the height, taps along the tile's and X's own "
        "motion, weighted by the share of each half-shutter a trail spends over X, the "
        "background behind filling the rest. docs/spec.md §17.6.",
    )
)


def tile_lines(frame: Frame, result: BlurResult | None = None, **params) -> twin.TileLines:
    """§17.6 steps 1–3: each pixel's half-motions and tile lines in `frame` at `params` (the
    NumPy twin's twin.tile_lines), on the tile grid of `result`, a run of gather_coverage on
    `frame` at the same tile parameters, where given (the twin's own otherwise)."""
    values = resolve_params(method("gather_coverage"), frame, params)
    dilated = None
    if result is not None:
        buffers = result.buffers
        dilated = (
            resolve_reach_keys(buffers["reach_keys"], buffers["tiles"])
            if "reach_keys" in buffers
            else buffers["dilated"]
        ).astype(np.float64)
    keywords = {key: values[key] for key in twin_keywords(twin.tile_lines)}
    return twin.tile_lines(frame.motion_prev, frame.motion_next, dilated=dilated, **keywords)


def tap_plan(
    frame: Frame,
    result: BlurResult | None = None,
    tiles: twin.TileLines | None = None,
    **params,
) -> twin.TapPlan:
    """§17.6.1: the taps each pixel of `frame` reads and the path it takes at `params` (the NumPy
    twin's twin.plan_taps: taps_per_pixel(), fast, half) on `tiles`, tile_lines(frame, result,
    **params) unless given (the lines do not depend on the options of §17.6.1)."""
    values = resolve_params(method("gather_coverage"), frame, params)
    if tiles is None:
        tiles = tile_lines(frame, result, **params)
    keywords = {key: values[key] for key in twin_keywords(twin.plan_taps)}
    return twin.plan_taps(tiles, **keywords)
