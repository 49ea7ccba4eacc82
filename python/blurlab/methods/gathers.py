"""What the engines' gathers along the motion share (docs/spec.md §4): the edge rules of
"Blurry things" (clamp, ignore, or a guard band re-rendered around the frame), the run of a
gather with them, and the box gather's parameters (shaders/common/box_gather.glsl; NumPy twin
blurlab.twins.gathers.box_gather). The gathers themselves are method folders:
gather_weighted/, gather_box/, gather_gaussian/ and camera_only/, which gathers the box along
the camera's motion alone.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..core.context import Context
from ..core.frame import Frame
from ..core.render import render_targets
from .core import PARAM_SCALE_MAX, Param, Pass, PassRunner

EDGES = ("clamp", "ignore", "guard")


def with_edge(ctx: Context, frame: Frame, inputs: dict, edge: str, reach: float, run):
    """Runs `run(inputs) -> (color texture, timings)` on the frame, or, for edge "guard", on
    the frame re-rendered with a margin wide enough for every tap, then crops the margin."""
    if edge != "guard":
        return run(inputs)
    if frame.scene is None or frame.time is None:
        raise ValueError(
            "blurlab: edge='guard' re-renders the frame with a margin, so it needs a frame "
            "made by ctx.render; use edge='clamp' or 'ignore' for frames built from arrays"
        )
    guard = math.ceil(reach * frame.longest_motion) + 2
    big, _, timing = render_targets(ctx, frame.scene, frame.size, frame.shutter, frame.time, guard)
    color, timings = run(big)
    height, width = frame.shape
    result = ctx.pooled((height, width, 4))
    result.native.copy_from(color.native, guard, guard)
    ctx.recycle(color, *big.values())
    return result, {"guard_gbuffer": timing, **timings}


def run_gather(step: Pass, params: dict[str, Param], reach: Callable[[dict], float]):
    """A gather's run function (a Declaration's): the pass named as `step` over the frame's
    color and motion, inside a guard band where edge="guard" (`reach`: the farthest tap, in
    motion lengths)."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
        def on(textures):
            runner = PassRunner(ctx, params, values)
            gathered = {"color": textures["color"], "motion": textures["motion"]}
            return runner.run_result(passes[step.name], gathered, backend), runner.timings

        color, timings = with_edge(ctx, frame, inputs, values["edge"], reach(values), on)
        return {"color": color}, timings

    return run


def edge_gather(step: Pass, params: dict[str, Param], reach) -> dict:
    """The Declaration fields of a gather with the edge rules: `step` run by run_gather on both
    backends (`reach` as run_gather's)."""
    return {
        "kind": "gather",
        "params": params,
        "passes": (step,),
        "backends": ("compute", "fragment"),
        "run": run_gather(step, params, reach),
    }


EDGE_PARAM = Param(
    "clamp", EDGES, "taps outside the image: clamp, ignore, or guard (re-render a margin)"
)

# The box gather's parameters, for the gathers of common/box_gather.glsl (and the intensity
# another method's gather shares).
BOX_PARAMS = {
    "taps": Param(10, int, "n equal taps", 2, 256),
    "intensity": Param(
        1.0, float, "length of the blur, fraction of the motion", 0, PARAM_SCALE_MAX
    ),
    "direction": Param("backward", ("backward", "centered"), "taps behind X, or around it"),
    "edge": EDGE_PARAM,
}


def box_reach(values: dict) -> float:
    return values["intensity"] * (0.5 if values["direction"] == "centered" else 1.0)


def box_instant(values: dict) -> str:
    """Taps around X read the G-buffer at the shutter's center, taps behind it at its close."""
    return "center" if values.get("direction") == "centered" else "close"
