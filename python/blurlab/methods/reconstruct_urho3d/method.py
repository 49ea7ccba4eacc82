"""reconstruct_urho3d: the reconstruct pass of the Urho3D thesis as printed there, a fragment
pass kept as the seed's baseline (docs/spec.md §3.5, a variant of §3; spec.md here). Shader
reconstruct.glsl beside this file (its header lists the differences from §3.4), NumPy twin
twin.reconstruct_urho3d. Parameters: TILE_FILTER_PARAMS (the seed picks the 64 x 64 jitter
texture) and `far` (FAR, shared with another filter that reads depth the Urho3D way), both
from blurlab/methods/tile_filter.py.
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ..core import Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..tile_filter import FAR, TILE_FILTER_PARAMS, reconstruct_on_tiles
from .twin import jitter_texture, reconstruct_urho3d

PARAMS = {**TILE_FILTER_PARAMS, "far": FAR}
# The seed picks the jitter texture; it is no uniform of the shader.
RECONSTRUCT = Pass(
    "reconstruct",
    shader_beside(__file__, "reconstruct.glsl"),
    ("k", "samples", "soft_z", "exposure", "far"),
)


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    runner = PassRunner(ctx, PARAMS, values)
    seed = values["seed"]
    jitter = ctx.cached(("urho3d_jitter", seed), lambda: ctx.upload(jitter_texture(seed)))
    textures = {name: inputs[name] for name in ("color", "depth", "motion")}
    textures["jitter"] = jitter
    return reconstruct_on_tiles(runner, RECONSTRUCT, textures, inputs["motion"], backend)


METHOD = Declaration(
    name="reconstruct_urho3d",
    kind="filter",
    order=3,
    params=PARAMS,
    passes=(RECONSTRUCT,),
    backends=("fragment",),
    run=run,
    default_grid={"k": [20], "samples": [9, 15]},
    twin=reconstruct_urho3d,
    gallery=True,
    doc="The reconstruct pass of the Urho3D thesis as printed there: a fragment pass, the "
    "seed's baseline. docs/spec.md §3 variant; the shader's header lists the differences.",
)
