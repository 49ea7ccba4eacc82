"""The four ways to blur translucent surfaces (docs/spec.md §20.4), for every method: one
framework-level option of ``blur`` and ``render_and_blur``, ``translucency``, and its threshold
``motion_coverage``, declared here once.

- "composite": blur the composite an engine shows, with the opaque layer's motion (engines'
  default). The plain blur of the frame, bit for bit.
- "composite_motion": the same, but where the translucent layer's coverage reaches
  `motion_coverage` its dominant fragment writes its own motion and depth (HDRP's option).
- "unblurred": blur the opaque layer, then composite the translucent layer over it unblurred
  (Unreal's order).
- "layered": blur the opaque layer and the translucent (Σ, a) layer each with its own motion,
  then out = Σ′ + (1 − a′)·opaque′.

Frames without a translucent layer (opaque scenes, or frames built from arrays without one) are
blurred as they are under every option, and so is every frame given to a method that renders
its own sub-frames (accumulation, stochastic): each of its sub-frames is composited exactly.
"""

from __future__ import annotations

import warnings
import weakref

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..core.graph import Node, run_graph, wire
from .params import Param, typed
from .passes import frame_textures, timed
from .registry import method, methods, translucent_layer_method

TRANSLUCENCY = Param(
    "composite",
    ("composite", "composite_motion", "unblurred", "layered"),
    "how translucent surfaces are blurred (docs/spec.md §20.4)",
)
MOTION_COVERAGE = Param(
    0.5,
    float,
    "composite_motion: the translucent coverage from which a surface writes its own motion",
    0.0,
    1.0,
)
LAYER_FILTER = Param(
    "auto",
    object,  # checked by layer_filter_method: "auto", "same" or a one-frame method's name
    "layered: what blurs the translucent layer: auto (the method registered with "
    "translucent_layer, the coverage gather, at any instant), same (the call's own method), or "
    "a filter or gather method's name",
)
LAYER_FILTER_KINDS = ("filter", "gather")
# The start of blur's warning that a frame is not at the instant the method expects.
INSTANT_WARNING = r"blurlab: \S+ expects the G-buffer at"
LAYER_PARAMS = {
    "translucency": TRANSLUCENCY,
    "motion_coverage": MOTION_COVERAGE,
    "layer_filter": LAYER_FILTER,
}


def checked(name: str, **options) -> dict:
    """The options as blur takes them; errors name the method, the option and what is
    allowed."""
    values = {key: typed(name, key, value, LAYER_PARAMS[key]) for key, value in options.items()}
    if "layer_filter" in values:
        chosen = values["layer_filter"]
        allowed = [n for n in methods() if method(n).kind in LAYER_FILTER_KINDS]
        if not isinstance(chosen, str) or chosen not in ("auto", "same", *allowed):
            raise ValueError(
                f"blurlab: {name} parameter layer_filter must be 'auto', 'same' or one of "
                f"{', '.join(allowed)}, not {chosen!r}"
            )
    return values


def layer_textures(ctx: Context, frame: Frame) -> dict:
    """The frame's translucent layer on `ctx`: the rendered textures, or uploaded arrays."""
    textures = frame.textures
    names = ("opaque_color", "translucent", "translucent_motion")
    if all(k in textures and textures[k].context is ctx for k in names):
        return textures
    packed = np.concatenate(
        [
            frame.translucent_motion,
            frame.translucent_depth[..., None],
            np.zeros(frame.translucent_depth.shape + (1,), np.float32),
        ],
        axis=-1,
    )
    uploaded = {
        "opaque_color": ctx.upload(frame.opaque_color),
        "translucent": ctx.upload(frame.translucent),
        "translucent_motion": ctx.upload(np.ascontiguousarray(packed)),
    }
    frame.textures = {**frame.textures, **uploaded}
    return uploaded


# The layer frames made from a frame, by id(frame) and then by what they are ("opaque",
# "translucent", ("chosen", motion_coverage)), dropped with the frame: each is made once per
# frame, so calls after the first run no per-frame pass, upload or read-back, and the layer
# frames' recorded plans (docs/spec.md §18) replay.
_LAYER_FRAMES: dict[int, dict] = {}


def _made_once(ctx: Context, frame: Frame, key, make):
    """make() the first time `key` is asked of `frame` on `ctx`, the same object afterwards;
    the textures it keeps go back to the pool with the frame."""
    made = _LAYER_FRAMES.get(id(frame))
    if made is None or made["context"] is not ctx:
        if made is None:
            weakref.finalize(frame, _LAYER_FRAMES.pop, id(frame), None)
        made = _LAYER_FRAMES[id(frame)] = {"context": ctx}
    if key not in made:
        made[key] = make()
    return made[key]


# The passes that make and composite the layers, on the pass graph (docs/spec.md §1.2): each
# reads and writes the textures its shader names.
SPLIT = Node("translucent_split", "passes/translucent_split.comp")
CHOSEN = Node("translucency_motion", "passes/translucency_motion.comp")
OVER = Node("translucency_over", "passes/translucency_over.comp")


def _layer_pass(ctx: Context, node: Node, textures: dict, values: dict, time) -> dict:
    """Runs `node` on `textures` (by the names its shader reads) with the uniforms of `values`
    it declares, `time(run)` running and timing the dispatch; returns every image it wrote,
    pooled."""
    wired = ctx.cached(("layer graph", node), lambda: wire(ctx, [node], source="translucency"))
    return run_graph(
        ctx,
        wired,
        textures,
        values,
        run=lambda w, inputs, outputs, uniforms: time(
            lambda: w.shader.run(inputs, outputs, uniforms)
        ),
        source="translucency",
    )


def _frame_pass(ctx: Context, frame: Frame, node: Node, textures: dict, values: dict) -> dict:
    """A per-frame pass that makes a layer frame: timed into frame.timings, as the G-buffer's
    own passes are, and its outputs back to the pool with the frame."""

    def time(run):
        with ctx.timer() as timing:
            run()
        frame.timings[node.name] = timing

    written = _layer_pass(ctx, node, textures, values, time)
    weakref.finalize(frame, ctx.recycle, *written.values())
    return written


def opaque_frame(ctx: Context, frame: Frame) -> Frame:
    """The frame's opaque layer as a frame of `ctx` (docs/spec.md §20.3), made once per frame."""

    def make():
        textures = {**frame_textures(ctx, frame), **layer_textures(ctx, frame)}
        names = ("depth", "motion", "motion_sides")
        kept = {key: textures[key] for key in names if key in textures}
        return frame.with_textures({"color": textures["opaque_color"], **kept})

    return _made_once(ctx, frame, "opaque", make)


def translucent_frame(ctx: Context, frame: Frame) -> Frame:
    """The frame's translucent layer (Σ, a) as a frame of `ctx` with its dominant fragment's
    motion, depth and two-sided motion (docs/spec.md §20.4, layered), made once per frame from
    the rendered layer on the GPU (passes/translucent_split.comp); the pass's time goes to
    frame.timings["translucent_split"], as the G-buffer's own passes do."""

    def make():
        textures = layer_textures(ctx, frame)
        share_prev = np.float32(frame.instant_fraction)
        split_outputs = _frame_pass(
            ctx,
            frame,
            SPLIT,
            {"translucent_motion": textures["translucent_motion"]},
            {"share_prev": share_prev, "share_next": np.float32(1.0 - share_prev)},
        )
        return frame.with_textures(
            {
                "color": textures["translucent"],
                "motion": split_outputs["layer_motion"],
                "depth": split_outputs["layer_depth"],
                "motion_sides": split_outputs["layer_sides"],
            },
        )

    return _made_once(ctx, frame, "translucent", make)


def chosen_frame(ctx: Context, frame: Frame, motion_coverage: float) -> Frame:
    """composite_motion's frame: the composite with, where the coverage reaches
    `motion_coverage`, the dominant fragment's motion and depth (docs/spec.md §20.4), made once
    per frame and threshold (passes/translucency_motion.comp, its time in
    frame.timings["translucency_motion"])."""

    def make():
        textures = {**frame_textures(ctx, frame), **layer_textures(ctx, frame)}
        inputs = {
            "translucent": textures["translucent"],
            "translucent_motion": textures["translucent_motion"],
            "motion": textures["motion"],
            "depth": textures["depth"],
        }
        chosen = _frame_pass(ctx, frame, CHOSEN, inputs, {"motion_coverage": motion_coverage})
        return frame.with_textures(
            {
                "color": textures["color"],
                "depth": chosen["chosen_depth"],
                "motion": chosen["chosen_motion"],
            },
        )

    return _made_once(ctx, frame, ("chosen", motion_coverage), make)


# A layer whose fragments all move less than this (px) is still: a GPU leaves about 1e-5 px on
# still geometry (two projections of one point), and it is far below the coverage gather's
# early exit (early_exit, 0.5 px), which would keep every such pixel as it is anyway.
STILL_PX = 1e-3


def layer_still(frame: Frame) -> bool:
    """Whether no fragment of the frame's translucent layer moves (its motion is under
    STILL_PX everywhere: a still window, or no translucent surface in view)."""
    return frame.layer_moves < STILL_PX


def blur_layers(
    ctx: Context,
    frame: Frame,
    name: str,
    translucency: str,
    motion_coverage: float,
    layer_filter: str,
    blur,
):
    """Runs `blur(layer_frame, method)` (blurlab.methods.core.blur with the call's backend,
    timing and, for its own method, parameters bound) on the layers that `translucency` needs
    and composites them: a BlurResult whose textures add "opaque_blurred" (unblurred, layered)
    or "chosen_motion" and "chosen_depth" (composite_motion), and whose timings add the layer
    passes: "translucent_" + the layer method's passes for the layered blur, and
    "translucency_over". The layer frames are made once per frame (opaque_frame,
    translucent_frame, chosen_frame), their passes timed in frame.timings."""
    extra: dict = {}
    if translucency == "composite_motion":
        derived = chosen_frame(ctx, frame, motion_coverage)
        result = blur(derived, name)
        result.params = {
            **result.params,
            **{"translucency": translucency, "motion_coverage": motion_coverage},
        }
        result.textures.update(
            {"chosen_motion": derived.textures["motion"], "chosen_depth": derived.textures["depth"]}
        )
        return result
    result = blur(opaque_frame(ctx, frame), name)
    result.params = {**result.params, "translucency": translucency}
    layer = layer_textures(ctx, frame)["translucent"]
    if translucency == "layered":
        if layer_filter == "auto":
            layer_method = translucent_layer_method()
        else:
            layer_method = name if layer_filter == "same" else layer_filter
        result.params["layer_filter"] = layer_method
        coverage_gather = layer_method == translucent_layer_method()
        # Where no fragment of the layer moves, the coverage gather keeps every pixel as it is
        # (its early exit, §17.6): the layer is composited as rendered, the same bits, unblurred.
        if not (coverage_gather and _made_once(ctx, frame, "still", lambda: layer_still(frame))):
            with warnings.catch_warnings():
                if coverage_gather:
                    # The coverage gather reads the layer's colour, depth and two-sided motion
                    # alone, and the split makes that motion for the frame's own instant: it is
                    # right at any instant, so its warning about the instant does not apply.
                    warnings.filterwarnings("ignore", INSTANT_WARNING)
                layer_result = blur(translucent_frame(ctx, frame), layer_method)
            layer = layer_result.textures["color"]
            extra.update({f"translucent_{k}": t for k, t in layer_result.timings.items()})
    textures = {"layer": layer, "opaque": result.textures["color"]}
    out = _layer_pass(
        ctx, OVER, textures, {}, lambda run: timed(ctx, extra, "translucency_over", run)
    )["result"]
    result.textures["opaque_blurred"] = result.textures["color"]
    result.textures["color"] = out
    result.timings.update(extra)
    weakref.finalize(result, ctx.recycle, out)
    return result
