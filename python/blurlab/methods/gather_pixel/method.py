"""gather_pixel: the tile-free per-pixel gather of Bevy (0.14) and Unity URP, written from
their public documentation (spec.md here, docs/spec.md §17.9), not from their sources. One pass
(gather.glsl): mirrored taps along the pixel's own motion, as many as its speed asks for up to
`samples` on each side, a tap in front of the pixel dropped. NumPy twin: twin.gather_pixel.

Bevy's shutter_angle is `exposure` (blurlab's G-buffer motion already spans the shutter) and
its samples, the taps taken in each direction, are the most a pixel takes here. What it leaves
out: the engines' fixed sample count (here it follows the speed), their temporal anti-aliasing,
which Bevy's documentation counts on to hide the noise, and URP's camera-only mode (blurlab has
a camera-only method for that).
"""

from __future__ import annotations

from ..core import FLOAT32_MAX, SEED, Param, Pass, PassRunner
from ..folders import Declaration
from ..tile_filter import TILE_FILTER_PARAMS
from ..unreal import PARAMS as UNREAL_PARAMS
from .twin import gather_pixel

PARAMS = {
    "samples": Param(8, int, "most taps on each side of the pixel (Bevy's samples)", 1, 32),
    "spacing": Param(
        2.0, float, "pixels of half-motion per tap on each side", 0, FLOAT32_MAX, low_open=True
    ),
    "depth_extent": UNREAL_PARAMS["depth_extent"],  # a tap this far in front weighs 0
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
}


def run(ctx, frame, inputs: dict, values: dict, backend: str, passes: dict):
    runner = PassRunner(ctx, PARAMS, values)
    textures = {name: inputs[name] for name in ("color", "depth", "motion")}
    return {"color": runner.run_result(passes["gather"], textures, backend)}, runner.timings


METHOD = Declaration(
    name="gather_pixel",
    kind="gather",
    order=19,
    params=PARAMS,
    passes=(Pass("gather", "gather.glsl", tuple(PARAMS)),),
    backends=("compute", "fragment"),
    run=run,
    default_grid={"samples": [2, 4, 8]},
    twin=gather_pixel,
    engine_peer=True,
    doc="Bevy 0.14 / Unity URP: no tiles, mirrored taps along the pixel's own motion, "
    "their count from its speed, taps in front of it dropped. docs/spec.md §17.9.",
)
