"""trail (Urho3D thesis §2.3.1, accumulation by feedback): over a sequence of frames,
out_n = α·C_n + (1 − α)·out_{n−1} (docs/spec.md §4; spec.md here), with the accumulate pass
the reference sums with (shaders/passes/accumulate.comp, blurlab.core.references), so it
declares no pass of its own. It blends frames, so a single-shutter sweep has nothing to blend:
its kind is "sequence".
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...core.gl import Timing
from ...core.references import accumulate
from ..core import BlurResult, Param, timed
from ..folders import Declaration


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    alpha = values["alpha"]
    history = values["history"]
    if history is not None and not isinstance(history, BlurResult):
        raise TypeError("blurlab: trail history must be the previous frame's BlurResult or None")
    height, width = inputs["color"].shape[:2]
    result = ctx.pooled((height, width, 4))
    result.clear()

    def blend():
        if history is None:  # out_0 = C_0
            accumulate(ctx, inputs["color"], result, 1.0)
            return
        if history.textures["color"].shape != (height, width, 4):
            raise ValueError("blurlab: trail history has another size than the frame")
        accumulate(ctx, inputs["color"], result, alpha)
        accumulate(ctx, history.textures["color"], result, 1.0 - alpha)

    timings: dict[str, Timing] = {}
    timed(ctx, timings, "trail", blend)
    return {"color": result}, timings


METHOD = Declaration(
    name="trail",
    kind="sequence",
    order=7,
    instant="close",
    params={
        "alpha": Param(0.5, float, "weight of the current frame", 0, 1),
        "history": Param(None, object, "the previous frame's BlurResult (None: first frame)"),
    },
    passes=(),
    run=run,
    doc="Urho3D thesis §2.3.1: out_n = α·C_n + (1 - α)·out_{n-1}, feedback over a "
    "sequence. docs/spec.md §4.",
)
