"""Tile lists and indirect dispatch (docs/spec.md §9.3): a classify pass appends each tile to
the list of its class with an atomic counter per class, the counters being the work-group
counts of an indirect dispatch; a pass then runs over one list with glDispatchComputeIndirect
(ShaderPass.run_indirect in src/passes/shader_pass.h), one work group per listed tile, so a
class's work costs what its tiles need and nothing comes back to the host. The shaders' side is
shaders/common/tile_lists.glsl. motion_classes() is the NumPy twin of the motion classifier
(shaders/passes/tile_classify.glsl).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.context import Context
from ..core.gl import Texture
from ..twins.inputs import sanitize_motion
from . import plans
from .params import Param
from .passes import Pass, PassRunner, pass_uniforms, timed

# How a method with tile classes dispatches them: declared once, taken by every such method.
TILE_DISPATCH = Param(
    "lists",
    ("lists", "one"),
    "lists: each tile class's pass runs over its own tile list (indirect dispatch); one: one "
    "dispatch over every tile, each taking its class's path (the same bits)",
)
# The motion classifier's classes, in the order of their indices (tile_classify.glsl).
MOTION_CLASSES = ("still", "uniform", "mixed")
CLASSIFY = Pass("tile_classify", "passes/tile_classify.glsl")


@dataclass(frozen=True)
class TileLists:
    """The tiles of one frame by class, all on the GPU: each tile's class (an (rows, columns)
    uint32 texture), the counters as indirect-dispatch counts (one row of 4 texels per class:
    count, 1, 1, unused) and the lists (one row per class, one texel per tile of the grid)."""

    tile: int
    names: tuple[str, ...]
    classes: Texture
    counts: Texture
    lists: Texture

    @property
    def grid(self) -> tuple[int, int]:
        """(rows, columns) of tiles."""
        return self.classes.shape[:2]

    def recycle(self, ctx: Context) -> None:
        ctx.recycle(self.classes, self.counts, self.lists)


def empty_lists(ctx: Context, size: tuple[int, int], tile: int, names) -> TileLists:
    """Lists for an image of `size` (H, W) in tiles of `tile` px, one per class of `names`,
    their counters at zero (set from the host: a run that makes lists is never replayed as a
    dispatch plan, which would not set them again)."""
    if not (isinstance(tile, int) and tile >= 1):
        raise ValueError(f"blurlab: a tile is a whole number of pixels >= 1, not {tile!r}")
    rows, columns = -(-size[0] // tile), -(-size[1] // tile)
    if rows * columns > ctx.max_texture_size:
        raise ValueError(
            f"blurlab: {rows * columns} tiles of {tile} px do not fit one list "
            f"({ctx.max_texture_size} at most): take larger tiles"
        )
    recorder = plans.active_recorder()
    if recorder is not None:
        recorder.unfit()
    counts = ctx.pooled((1, 4 * len(names), 1), "uint32")
    counts.upload(np.tile(np.array([0, 1, 1, 0], np.uint32), len(names))[None, :, None])
    lists = ctx.pooled((len(names), rows * columns, 1), "uint32")
    return TileLists(tile, tuple(names), ctx.pooled((rows, columns, 1), "uint32"), counts, lists)


def classify_motion(
    ctx: Context,
    timings: dict,
    motion: Texture,
    tile: int,
    still_below: float = 0.5,
    uniform_ratio: float = 0.4,
) -> TileLists:
    """The tiles of `motion` in MOTION_CLASSES (tile_classify.glsl), timed under
    "tile_classify"."""
    lists = empty_lists(ctx, motion.shape[:2], tile, MOTION_CLASSES)
    shader = ctx.shader_pass(CLASSIFY.shader)
    outputs = {"tile_class": lists.classes, "tile_counts": lists.counts, "tile_lists": lists.lists}
    uniforms = {"tile": tile, "still_below": still_below, "uniform_ratio": uniform_ratio}
    timed(ctx, timings, CLASSIFY.name, lambda: shader.run({"motion": motion}, outputs, uniforms))
    return lists


def run_over_list(
    ctx: Context,
    timings: dict,
    step: Pass,
    lists: TileLists,
    cls: int,
    inputs: dict[str, Texture],
    outputs: dict[str, Texture],
    uniforms: dict | None = None,
    defines: dict | None = None,
    only_used: bool = False,
) -> None:
    """Runs `step`'s shader over the tiles of class `cls` only, one work group per tile, timed
    under "step.name[class name]". The shader reads its tile with listed_tile()
    (common/tile_lists.glsl): `inputs` gain the lists as "tile_lists" and its uniforms
    "tile_class". With `only_used`, inputs and uniforms that the compiled shader does not use
    are left out: a pass compiled once per class (a LIST_CLASS define) uses what its class
    reads."""
    if not 0 <= cls < len(lists.names):
        raise ValueError(f"blurlab: class {cls!r} is outside 0..{len(lists.names) - 1}")
    shader = ctx.shader_pass(step.shader, defines)
    inputs = {**inputs, "tile_lists": lists.lists}
    values = {**(uniforms or {}), "tile_class": cls}
    if only_used:
        used = ctx.cached(
            ("run_over_list", step.shader, tuple(sorted((defines or {}).items()))), shader.reflect
        )
        inputs = {name: t for name, t in inputs.items() if name in used["samplers"]}
        values = {name: v for name, v in values.items() if name in used["uniforms"]}
    native_inputs = {name: t.native for name, t in inputs.items()}
    native_outputs = {name: t.native for name, t in outputs.items()}

    def run():
        shader.native.run_indirect(native_inputs, native_outputs, values, lists.counts.native, cls)

    timed(ctx, timings, f"{step.name}[{lists.names[cls]}]", run)


def run_per_class(
    passes: PassRunner,
    step: Pass,
    lists: TileLists,
    classes,
    inputs: dict[str, Texture],
    outputs: dict[str, Texture],
    uniforms: dict | None = None,
    defines: dict | None = None,
) -> None:
    """Runs `step` once per class of `classes` over that class's list (run_over_list), each
    compiled with OVER_LIST and LIST_CLASS = the class (so that its program holds its class's
    path alone) and given the uniforms of the step's method parameters (passes' values)."""
    values = {**pass_uniforms(passes.params, passes.values, step.params), **(uniforms or {})}
    for cls in classes:
        run_over_list(
            passes.ctx,
            passes.timings,
            step,
            lists,
            cls,
            inputs,
            outputs,
            values,
            {**(defines or {}), "OVER_LIST": 1, "LIST_CLASS": cls},
            only_used=True,
        )


def motion_classes(motion, tile: int, still_below: float = 0.5, uniform_ratio: float = 0.4):
    """NumPy twin of tile_classify.glsl: (rows, columns) class indices of MOTION_CLASSES from
    each tile's longest and shortest |M| (float32 lengths, as the GPU computes them)."""
    m = sanitize_motion(motion).astype(np.float32)
    length = np.sqrt((m * m).sum(-1, dtype=np.float32), dtype=np.float32)
    h, w = length.shape
    rows, columns = -(-h // tile), -(-w // tile)
    longest = np.zeros((rows, columns), np.float32)
    shortest = np.full((rows, columns), np.inf, np.float32)
    for r in range(rows):
        for c in range(columns):
            block = length[r * tile : (r + 1) * tile, c * tile : (c + 1) * tile]
            longest[r, c], shortest[r, c] = block.max(), block.min()
    kind = np.where(shortest >= np.float32(uniform_ratio) * longest, 1, 2)
    return np.where(longest < still_below, 0, kind)
