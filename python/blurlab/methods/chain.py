"""The run of a method that is a chain of passes (a method folder's declaration): each pass
reads the frame's textures and the images earlier passes wrote, by the names its shader gives
its samplers, and writes its own images, one frame-sized texture each; the last pass's `result`
is the method's color. Everything is bound by name (ShaderPass.reflect), so a folder needs no
Python of its own to run."""

from __future__ import annotations

from ..context import Context
from ..frame import Frame
from .params import Param
from .passes import Pass, PassRunner, choice_defines

# An image format a pass may write, and the texture that holds it: (channels, dtype).
IMAGE_FORMATS = {
    "rgba32f": (4, "float32"),
    "rg32f": (2, "float32"),
    "r32f": (1, "float32"),
    "rgba16f": (4, "float16"),
}
RESULT = "result"  # the image (compute) or output (fragment) the last pass writes the color to


def chain_run(passes: tuple[Pass, ...], params: dict[str, Param], source: str):
    """The run function (Method.run) of `passes` run in order, each with the parameters it
    lists as uniforms; `source` names the declaration in errors."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        height, width = inputs["color"].shape[:2]
        available = {name: inputs[name] for name in ("color", "depth", "motion")}
        written: dict = {}
        runner = PassRunner(ctx, params, values)
        for index, step in enumerate(passes):
            last = index == len(passes) - 1
            shader = ctx.shader_pass(step.shader, choice_defines(params, step.params))
            reflected = shader.reflect(backend)
            missing = sorted(set(reflected["samplers"]) - set(available))
            if missing:
                raise ValueError(
                    f"blurlab: {source}: pass {step.name} reads {missing}, which neither the "
                    f"frame nor an earlier pass provides (there are {sorted(available)})"
                )
            images = reflected["images"] if backend == "compute" else reflected["fragment_outputs"]
            if last and RESULT not in images:
                raise ValueError(
                    f"blurlab: {source}: the last pass, {step.name}, writes no image named "
                    f"{RESULT!r}, the method's color (it writes {sorted(images)})"
                )
            outputs = {}
            for name, image in images.items():
                if name in available:
                    raise ValueError(
                        f"blurlab: {source}: pass {step.name} writes {name!r}, which the frame "
                        "or an earlier pass already provides; give each image its own name"
                    )
                fmt = image.get("format", "rgba32f")
                if fmt not in IMAGE_FORMATS:
                    raise ValueError(
                        f"blurlab: {source}: pass {step.name}'s image {name} is {fmt}; "
                        f"images may be {', '.join(IMAGE_FORMATS)}"
                    )
                channels, dtype = IMAGE_FORMATS[fmt]
                outputs[name] = ctx.pooled((height, width, channels), dtype)
            # The dispatch covers the first output: the result where there is one.
            if RESULT in outputs:
                outputs = {RESULT: outputs.pop(RESULT), **outputs}
            textures = {name: available[name] for name in reflected["samplers"]}
            runner.run(step, textures, outputs, backend)
            available.update(outputs)
            written.update(outputs)
        color = written.pop(RESULT)
        return {"color": color, **written}, runner.timings

    return run
