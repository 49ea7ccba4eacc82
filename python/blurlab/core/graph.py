"""Passes wired as a graph (docs/spec.md §1.2): each pass is known by its shader, and its
inputs and outputs are the shader's own samplers and images (ShaderPass.reflect), so a chain of
passes is declared by naming shaders, never by wiring textures by hand. A pass reads the graph's
input textures and the images earlier passes wrote, by name; its images are pooled textures of
the size of what it reads, given back to the pool after the last pass that reads them, unless a
caller keeps them. Nothing crosses to the host."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

# An image format a pass may write, and the texture that holds it: (channels, dtype).
IMAGE_FORMATS = {
    "rgba32f": (4, "float32"),
    "rg32f": (2, "float32"),
    "r32f": (1, "float32"),
    "rgba16f": (4, "float16"),
    "r32ui": (1, "uint32"),
}


@dataclass(frozen=True)
class Node:
    """One pass of a graph: `name` keys its timing; `shader` (a path under the shader folder,
    or absolute) compiled with `defines`; `reads` maps a sampler to the texture it reads where
    their names differ, `writes` an image to the texture it becomes; `first_output` names the
    image the dispatch covers (default: the first the shader declares); `size_of` the texture
    whose (H, W) its images take (default: the first it reads)."""

    name: str
    shader: str
    defines: tuple[tuple[str, object], ...] = ()
    reads: tuple[tuple[str, str], ...] = ()
    writes: tuple[tuple[str, str], ...] = ()
    first_output: str | None = None
    size_of: str | None = None
    group_per_texel: bool = False


@dataclass(frozen=True)
class Wired:
    """A node resolved against its shader's reflection: sampler -> texture read, image ->
    (texture written, channels, dtype), and the uniforms the shader declares."""

    node: Node
    shader: object  # blurlab.core.gl.ShaderPass
    inputs: dict
    outputs: dict
    uniforms: tuple[str, ...]


def wire(ctx, nodes, backend: str = "compute", source: str = "graph") -> list[Wired]:
    """Resolves every node's inputs and outputs from its shader on `ctx` (compiling it once
    per context); `source` names the graph in errors."""
    wired = []
    for node in nodes:
        shader = ctx.shader_pass(node.shader, dict(node.defines))
        reflected = shader.reflect(backend)
        reads, writes = dict(node.reads), dict(node.writes)
        images = reflected["images"] if backend == "compute" else reflected["fragment_outputs"]
        outputs = {}
        for image, info in images.items():
            fmt = info.get("format", "rgba32f")
            if fmt not in IMAGE_FORMATS:
                raise ValueError(
                    f"blurlab: {source}: pass {node.name}'s image {image} is {fmt}; images "
                    f"may be {', '.join(IMAGE_FORMATS)}"
                )
            outputs[image] = (writes.get(image, image), *IMAGE_FORMATS[fmt])
        first = node.first_output
        if first is not None:
            if first not in outputs:
                raise ValueError(
                    f"blurlab: {source}: pass {node.name} has no image {first!r} to dispatch "
                    f"over (it writes {sorted(outputs)})"
                )
            outputs = {first: outputs.pop(first), **outputs}
        inputs = {sampler: reads.get(sampler, sampler) for sampler in reflected["samplers"]}
        wired.append(Wired(node, shader, inputs, outputs, tuple(reflected["uniforms"])))
    return wired


def run_graph(
    ctx,
    wired: list[Wired],
    textures: Mapping,
    values: Mapping | None = None,
    keep=None,
    run: Callable | None = None,
    source: str = "graph",
) -> dict:
    """Runs the wired passes in order on `textures` (name -> Texture): each pass gets the
    uniforms of `values` its shader declares. Returns the textures of the names in `keep`
    (None: every image written); the other images go back to the pool after their last
    reader. `run(wired, inputs, outputs, uniforms)` runs one pass (default: the shader, untimed);
    a method's passes run through its PassRunner, timed and recorded."""
    values = dict(values or {})
    last_read: dict[str, int] = {}
    for index, w in enumerate(wired):
        for name in w.inputs.values():
            last_read[name] = index
    available = dict(textures)
    made: dict = {}
    for index, w in enumerate(wired):
        missing = sorted(name for name in w.inputs.values() if name not in available)
        if missing:
            raise ValueError(
                f"blurlab: {source}: pass {w.node.name} reads {missing}, which neither the "
                f"inputs nor an earlier pass provide (there are {sorted(available)})"
            )
        inputs = {sampler: available[name] for sampler, name in w.inputs.items()}
        sized = available[w.node.size_of] if w.node.size_of else next(iter(inputs.values()), None)
        if sized is None:
            raise ValueError(f"blurlab: {source}: pass {w.node.name} reads nothing to size by")
        height, width = sized.shape[:2]
        outputs = {}
        for image, (name, channels, dtype) in w.outputs.items():
            if name in available:
                raise ValueError(
                    f"blurlab: {source}: pass {w.node.name} writes {name!r}, which the inputs "
                    "or an earlier pass already provide; give each image its own name"
                )
            # one channel is an (H, W) texture, as the G-buffer's depth is
            shape = (height, width) if channels == 1 else (height, width, channels)
            outputs[image] = ctx.pooled(shape, dtype)
        uniforms = {name: values[name] for name in w.uniforms if name in values}
        if run is None:
            w.shader.run(inputs, outputs, uniforms, group_per_texel=w.node.group_per_texel)
        else:
            run(w, inputs, outputs, uniforms)
        for image, texture in outputs.items():
            name = w.outputs[image][0]
            available[name] = made[name] = texture
        for name in list(made):  # read by no later pass, and not asked for: back to the pool
            if last_read.get(name, -1) <= index and keep is not None and name not in keep:
                ctx.recycle(made.pop(name))
                del available[name]
    return dict(made) if keep is None else {name: made[name] for name in keep if name in made}
