"""accumulation (Haeberli-Akeley; the OGRE paper): the converged reference of docs/spec.md §11
with a small N (4-32), which shows banding where N is below the motion's length in pixels
(docs/spec.md §4; spec.md here). It renders its sub-frames itself through ctx.reference
(blurlab.core.references), so it declares no pass of its own.
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...core.gl import Timing
from ..core import SEED, Param
from ..folders import Declaration


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
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
    height, width = frame.shape
    result = ctx.pooled((height, width, 4))
    result.native.copy_from(reference.texture.native, 0, 0)
    timing = Timing(reference.ms_per_subframe * reference.samples, reference.clock)
    return {"color": result}, {"accumulation": timing}


METHOD = Declaration(
    name="accumulation",
    kind="render",
    order=8,
    params={
        "samples": Param(8, int, "sub-frames N; 4-32 shows the banding", 1, 4096),
        "stratified": Param("uniform", ("uniform", "stratified"), "sub-frame times"),
        "seed": SEED,
    },
    passes=(),
    run=run,
    default_grid={"samples": [4, 8, 16]},
    renders_for=lambda n: {"samples": n},
    doc="Haeberli-Akeley accumulation (the OGRE paper): the reference with small N. "
    "docs/spec.md §4.",
)
