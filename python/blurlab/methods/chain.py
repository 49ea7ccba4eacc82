"""The run of a method that is a chain of passes (a method folder's declaration), on the pass
graph (blurlab.core.graph, docs/spec.md §1.2): each pass reads the frame's textures and the images
earlier passes wrote, by the names its shader gives its samplers, and writes its own images, one
frame-sized texture each; the last pass's `result` is the method's color. Everything is bound by
name (ShaderPass.reflect), so a folder needs no Python of its own to run."""

from __future__ import annotations

from ..core.context import Context
from ..core.frame import Frame
from ..core.graph import Node, run_graph, wire
from .params import Param
from .passes import Pass, PassRunner, choice_defines

RESULT = "result"  # the image (compute) or output (fragment) the last pass writes the color to


def chain_run(passes: tuple[Pass, ...], params: dict[str, Param], source: str):
    """The run function (Method.run) of `passes` run in order, each with the parameters it
    lists as uniforms; `source` names the declaration in errors."""
    by_name = {step.name: step for step in passes}

    def wired(ctx: Context, backend: str):
        """The passes wired from their shaders' reflection, once per context and backend."""
        nodes = [
            Node(step.name, step.shader, defines=tuple(choice_defines(params, step.params).items()))
            for step in passes
        ]
        reflected = wire(ctx, nodes, backend, source)
        last = reflected[-1]
        if RESULT not in last.outputs:
            raise ValueError(
                f"blurlab: {source}: the last pass, {last.node.name}, writes no image named "
                f"{RESULT!r}, the method's color (it writes {sorted(last.outputs)})"
            )
        # The dispatch covers the first output: the result where a pass writes one.
        nodes = [
            Node(n.name, n.shader, n.defines, first_output=RESULT if RESULT in w.outputs else None)
            for n, w in zip(nodes, reflected, strict=True)
        ]
        return wire(ctx, nodes, backend, source)

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        # Keyed by this declaration's own function: a folder loaded again wires its passes anew.
        chain = ctx.cached(("method chain", wired, backend), lambda: wired(ctx, backend))
        runner = PassRunner(ctx, params, values)

        def run_pass(w, textures, outputs, uniforms):
            runner.run(by_name[w.node.name], textures, outputs, backend)

        frame_inputs = {name: inputs[name] for name in ("color", "depth", "motion")}
        written = run_graph(ctx, chain, frame_inputs, run=run_pass, source=source)
        color = written.pop(RESULT)
        return {"color": color, **written}, runner.timings

    return run
