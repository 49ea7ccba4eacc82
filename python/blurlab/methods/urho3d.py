"""reconstruct_urho3d: the reconstruct pass of the Urho3D thesis as printed there, a fragment
pass kept as the seed's baseline (docs/spec.md §3, variant). Shader
shaders/passes/reconstruct_urho3d.glsl (its header lists the differences from §3.4), NumPy twin
blurlab.twins.urho3d.reconstruct_urho3d. Parameters: TILE_FILTER_PARAMS (the seed picks
the 64 x 64 jitter texture) and `far`, declared here.
"""

from __future__ import annotations

from ..core.context import Context
from ..core.frame import Frame
from ..twins import urho3d as twin
from .core import FLOAT32_MAX, Method, Param, Pass, PassRunner, register
from .tile_filter import TILE_FILTER_PARAMS, reconstruct_on_tiles


def default_far(frame: Frame) -> float:
    """The depth the Urho3D pass reads for +inf: the camera's far plane for rendered frames,
    else twice the largest finite depth."""
    if frame.camera is not None and "far" in frame.camera:
        return float(frame.camera["far"])
    if frame.depth_range is None or frame.depth_range[1] <= 0:
        return 1.0
    return min(2.0 * frame.depth_range[1], FLOAT32_MAX)  # finite even for depths near 3.4e38


PARAMS = {
    **TILE_FILTER_PARAMS,
    "far": Param(default_far, float, "depth that +inf is read as", 0, FLOAT32_MAX, low_open=True),
}
# The seed picks the jitter texture; it is no uniform of the shader.
RECONSTRUCT = Pass(
    "reconstruct",
    "passes/reconstruct_urho3d.glsl",
    ("k", "samples", "soft_z", "exposure", "far"),
)


def _run_urho3d(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    passes = PassRunner(ctx, PARAMS, values)
    seed = values["seed"]
    jitter = ctx.cached(("urho3d_jitter", seed), lambda: ctx.upload(twin.jitter_texture(seed)))
    textures = {name: inputs[name] for name in ("color", "depth", "motion")}
    textures["jitter"] = jitter
    return reconstruct_on_tiles(passes, RECONSTRUCT, textures, inputs["motion"], backend)


register(
    Method(
        name="reconstruct_urho3d",
        kind="filter",
        params=PARAMS,
        backends=("fragment",),
        run=_run_urho3d,
        default_grid={"k": [20], "samples": [9, 15]},
        twin=twin.reconstruct_urho3d,
        gallery=True,
        doc="The reconstruct pass of the Urho3D thesis as printed there: a fragment pass, the "
        "seed's baseline. docs/spec.md §3 variant; the shader's header lists the differences.",
    )
)
