"""Temporal anti-aliasing as a pass (docs/spec.md §21.2): the history reprojected by the motion
buffer, held to the current frame's YCoCg neighbourhood, blended exponentially
(shaders/passes/taa.comp; NumPy twin blurlab.twins.taa.resolve; test tests/test_taa.py).

Its parameters are declared here once, as a method's are (`PARAMS`), and validated by the same
check (`blurlab.methods.params.typed`):

| parameter | default | allowed | what |
|---|---|---|---|
| `blend` | 0.1 | (0, 1] | weight w of the current frame once the history is full |
| `clip` | "clip" | clip, clamp, none | how the history is held to the neighbourhood |
| `neighbourhood` | "3x3" | 3x3, cross | the current pixels whose YCoCg box bounds the history |
"""

from __future__ import annotations

from ..core.context import Context
from ..core.gl import Texture
from ..core.graph import Node, run_graph, wire
from ..methods.core import Pass
from ..methods.params import Param, typed
from ..methods.passes import PassRunner, choice_defines
from ..twins.taa import NEIGHBOURHOODS

PARAMS = {
    "blend": Param(
        0.1,
        float,
        "weight w of the current frame in out = (1 - w)·history + w·current once the history "
        "holds 1/w frames (before that, 1/n for its n frames)",
        0.0,
        1.0,
        low_open=True,
    ),
    "clip": Param(
        "clip",
        ("clip", "clamp", "none"),
        "how the history is held to the current neighbourhood's YCoCg box: clipped toward the "
        "box's centre, clamped per channel, or kept as it is",
    ),
    "neighbourhood": Param(
        "3x3",
        tuple(NEIGHBOURHOODS),
        "the current pixels whose YCoCg box bounds the history: the 3x3 block, or the pixel "
        "and its four edge neighbours",
    ),
}
RESOLVE = Pass("taa", "passes/taa.comp", tuple(PARAMS))


def _wired(ctx: Context):
    """TAA on the pass graph (docs/spec.md §1.2): its pass bound by the shader's own names
    (current, motion, history -> resolved), wired once per context."""
    node = Node(RESOLVE.name, RESOLVE.shader, tuple(choice_defines(PARAMS, RESOLVE.params).items()))
    return ctx.cached(("taa graph",), lambda: wire(ctx, [node], source="taa"))


def taa_values(**given) -> dict:
    """Every TAA parameter's value for `given` (the rest at their defaults), validated."""
    unknown = set(given) - set(PARAMS)
    if unknown:
        raise TypeError(
            f"blurlab: taa has no parameter(s) {sorted(unknown)}; its parameters are "
            + ", ".join(f"{k} (default {p.default!r})" for k, p in PARAMS.items())
        )
    return {k: typed("taa", k, given.get(k, p.default), p) for k, p in PARAMS.items()}


def taa(
    ctx: Context,
    current: Texture,
    motion: Texture,
    history: Texture | None,
    timings: dict | None = None,
    **params,
) -> Texture:
    """One TAA frame on the GPU: a new pooled (H, W, 4) texture with the resolved colour and,
    in alpha, how many frames its history holds. `current` is this frame's colour, `motion` the
    (H, W, 2) motion from the previous frame to this one in pixels (+y down), `history` the
    previous call's output or None on the first frame. `timings` (a dict) gets the pass's
    Timing under "taa"."""
    values = taa_values(**params)
    height, width = current.shape[:2]
    for name, texture in (("motion", motion), ("history", history)):
        if texture is not None and texture.shape[:2] != (height, width):
            raise ValueError(
                f"blurlab: taa {name} is {texture.shape[1]}x{texture.shape[0]}, the current "
                f"colour {width}x{height}: give both at the same size"
            )
    runner = PassRunner(ctx, PARAMS, values, {} if timings is None else timings)
    has_history = {"has_history": int(history is not None)}
    written = run_graph(
        ctx,
        _wired(ctx),
        {"current": current, "motion": motion, "history": current if history is None else history},
        keep=("resolved",),
        run=lambda w, inputs, outputs, uniforms: runner.run(
            RESOLVE, inputs, outputs, uniforms=has_history
        ),
        source="taa",
    )
    return written["resolved"]
