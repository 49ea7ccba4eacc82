"""gather_coverage: a post-process filter built from what measured best among the engines' and
the papers' filters (spec.md here, docs/spec.md §17.6): the two-sided motion and the dilation
along each tile's motion of engine_eevee, tile size and blur limit relative to the image height
as engine_unity's, taps along the neighbourhood's and X's own motion (Guertin 2014's two
directions, Unity's v_alt), and weights that estimate what share of each half-shutter a moving
pixel spends over X, with what lies behind X filling the rest. Passes: engine_eevee's tile
flatten and dilation at this method's tile size and limit (methods.eevee.dilated_tiles), the
dilation by scatter (keys cleared, the flatten offering each tile's reach by atomic max:
shaders/passes/reach_keys_clear.glsl, eevee_tile_flatten.glsl; §17.6), then gather.glsl, which
resolves the keys itself unless eevee.DILATION_LAYOUT says a pass of their own does
(eevee_tile_resolve.glsl), then, where film_filter > 0, film_filter.glsl, unless
film_through_taps reads the filter through the gather's colour reads instead. The options of
§17.6.1 (tap_spacing, early_exit, uniform_tolerance, half_res_above) spend the gather's taps
where the motion needs them; half_res_above adds a pass of the same shader at half resolution
before the gather (gather_half). NumPy twin: twin.gather_coverage; blurlab.methods.coverage
holds its parameters, its passes' layouts and tap_plan, which gives each pixel's taps and path.
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...twins import coverage as parts
from ...twins import film
from .. import tiles as tile_lists
from ..core import Pass, PassRunner, shader_beside
from ..coverage import FILM_LAYOUT, GATHER_LAYOUT, PARAMS
from ..eevee import dilated_tiles
from ..folders import Declaration
from .twin import gather_coverage

GATHER = Pass(
    "gather",
    shader_beside(__file__, "gather.glsl"),
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
FILM = Pass("film", shader_beside(__file__, "film_filter.glsl"), ("film_filter",))
FILM_ROWS = Pass("film_rows", FILM.shader, FILM.params)
FILM_COLUMNS = Pass("film_columns", FILM.shader, FILM.params)


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
    lists = tile_lists.empty_lists(ctx, gathered.shape[:2], LIST_BLOCK, parts.BLOCK_CLASSES)
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
    classes = range(len(parts.BLOCK_CLASSES))
    into = {"result": gathered}
    tile_lists.run_per_class(passes, GATHER, lists, classes, textures, into, uniforms, defines)
    return lists


def run(
    ctx: Context,
    frame: Frame,
    inputs: dict,
    values: dict,
    backend: str,
    passes: dict | None = None,
):
    """The method's passes (docs/spec.md §17.6). The gather runs over two lists of 16 px blocks,
    still (each pixel keeps its colour) and moving (§17.6.2), unless half_res_above is on or
    tile_dispatch is "one": then one pass covers every pixel, with the same bits. It runs the
    module's passes; `passes`, the declared ones by name, is not read."""
    size = inputs["color"].shape[:2]
    s = parts.tile_size(size[0], values["tile_percent"])
    reach_limit = parts.max_blur_px(size[0], values["max_blur"])
    runner = PassRunner(ctx, PARAMS, values)
    grids = dilated_tiles(
        ctx,
        frame,
        runner.timings,
        PARAMS,
        values,
        size,
        s,
        reach_limit,
        length_steps=parts.TILE_LENGTH_STEPS,
        jitter_reach=parts.JITTER_REACH,
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
        runner.run(GATHER_HALF, textures, {"result": half}, backend, uniforms, half_defines)
        textures["half_gathered"] = half
    lists = None
    on_lists = values["tile_dispatch"] == "lists" and values["half_res_above"] == 0
    if on_lists and backend == "compute":
        lists = _gather_over_lists(runner, textures, gathered, uniforms, defines)
    else:
        runner.run(GATHER, textures, {"result": gathered}, backend, uniforms, defines)
    if values["half_res_above"] > 0:
        ctx.recycle(half)
    outputs = {"color": gathered, **tile_buffers}
    if lists is not None:
        outputs.update(tile_counts=lists.counts, block_class=lists.classes)
        ctx.recycle(lists.lists)
    if values["film_filter"] > 0 and not through_taps:
        outputs.update(color=_film_filter(runner, gathered), unfiltered=gathered)
    return outputs, runner.timings


METHOD = Declaration(
    name="gather_coverage",
    kind="gather",
    order=18,
    params=PARAMS,
    # The passes a call at the defaults runs under their own names (the contract checks each is
    # timed): the gather is timed per block list (gather[still], gather[moving]) or, with
    # tile_dispatch "one" or half_res_above, as gather; gather_half and the film filter run only
    # with their options; the tile passes are engine_eevee's (methods/eevee.py).
    passes=(BLOCK_CLASSIFY,),
    run=run,
    tile_lists=parts.BLOCK_CLASSES,
    default_grid={"samples": [4, 8, 16], "max_blur": [15.0, 30.0]},
    twin=gather_coverage,
    translucent_layer=True,
    # film_through_taps reads film_filter as a 3-tap filter: up to 0.71 px (§17.6)
    linked_params=(("film_through_taps", "film_filter"),),
    doc="The engines' best parts combined: two-sided motion, dilation along each tile's "
    "motion, tiles and limit relative to the height, taps along the tile's and X's own "
    "motion, weighted by the share of each half-shutter a moving pixel spends over X, the "
    "background behind filling the rest. docs/spec.md §17.6.",
)
