"""engine_godot: the motion blur of Godot's motion-blur pull request (godotengine/godot#115027)
and the addon it grew from, written from the design they document, not from their shaders
(spec.md here, docs/spec.md §17.10). The velocity pass (velocity.glsl) splits the motion
into camera rotation, camera translation and object parts, each with its own multiplier, clamps
the sum to the largest multiplier times the original vector, corrects ends behind the near
plane and keeps the camera's depth velocity, all scaled by the frame-rate mode; TileMax and
NeighborMax (the direction-keeping dilation) of its half-vectors, clamped to the tile size k;
then a gather centred on the pixel with the quality preset's 4, 8 or 16 taps
(reconstruct.glsl). NumPy twin: twin.engine_godot.

What it leaves out: the addon's sky pre-pass (blurlab's G-buffer already gives the sky its
motion), FSR2 support and its own blending heuristics, which its documentation does not give.
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ..camera_motion import split_camera_uniforms
from ..core import Param, Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..tile_filter import TILE_FILTER_PARAMS, tile_passes
from . import twin

MULTIPLIER_DOC = "multiplier of the {} part of the motion"
FRAME_RATE_MAX = 1000.0
PARAMS = {
    "quality": Param("medium", tuple(twin.SAMPLES_BY_QUALITY), "preset: 4, 8 or 16 samples"),
    "k": TILE_FILTER_PARAMS["k"],
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "soft_z": TILE_FILTER_PARAMS["soft_z"],
    "rotation_multiplier": Param(1.0, float, MULTIPLIER_DOC.format("camera rotation"), 0, 1),
    "translation_multiplier": Param(1.0, float, MULTIPLIER_DOC.format("camera translation"), 0, 1),
    "object_multiplier": Param(1.0, float, MULTIPLIER_DOC.format("object"), 0, 1),
    "clamp_to_original": Param(
        True, bool, "clamp |V| to the largest multiplier times the original vector's length"
    ),
    "near_correction": Param(
        True, bool, "move ends closer than the near plane back to where they crossed it"
    ),
    "depth_velocity": Param(True, bool, "compare depths at each tap's time (depth velocity)"),
    "framerate_mode": Param(
        "native", twin.FRAMERATE_MODES, "blur as the frame's motion, capped or fixed at a rate"
    ),
    "fps": Param(
        60.0, float, "the rate the frame is shown at, frames/s", 0, FRAME_RATE_MAX, low_open=True
    ),
    "reference_fps": Param(
        30.0,
        float,
        "reference rate of the capped and fixed modes, frames/s",
        0,
        FRAME_RATE_MAX,
        low_open=True,
    ),
    "seed": TILE_FILTER_PARAMS["seed"],
}
VELOCITY_PARAMS = (
    "rotation_multiplier",
    "translation_multiplier",
    "object_multiplier",
    "clamp_to_original",
    "near_correction",
    "depth_velocity",
)
VELOCITY = Pass("velocity", shader_beside(__file__, "velocity.glsl"), VELOCITY_PARAMS)
RECONSTRUCT = Pass(
    "reconstruct", shader_beside(__file__, "reconstruct.glsl"), ("k", "exposure", "soft_z", "seed")
)


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    height, width = inputs["color"].shape[:2]
    runner = PassRunner(ctx, PARAMS, values)
    camera = split_camera_uniforms(frame.camera)
    scale = twin.framerate_scale(values["framerate_mode"], values["fps"], values["reference_fps"])
    velocity = ctx.pooled((height, width, 4))
    runner.run(
        passes["velocity"],
        {"depth": inputs["depth"], "motion": inputs["motion"]},
        {"velocity": velocity},
        uniforms={**camera, "framerate_scale": scale, "flip_guard": twin.FLIP_GUARD},
    )
    tiles, neighbors = tile_passes(
        runner, velocity, "compute", diagonal_reach=True, length_key_steps=twin.LENGTH_KEY_STEPS
    )
    textures = {"color": inputs["color"], "velocity": velocity, "neighbor_max": neighbors}
    taps = twin.SAMPLES_BY_QUALITY[values["quality"]]
    result = runner.run_result(passes["reconstruct"], textures, backend, uniforms={"taps": taps})
    outputs = {"color": result, "velocity": velocity, "tile_max": tiles, "neighbor_max": neighbors}
    return outputs, runner.timings


METHOD = Declaration(
    name="engine_godot",
    kind="gather",
    order=17,
    params=PARAMS,
    # TileMax and NeighborMax are the tile filters' (shaders/passes), run by tile_passes.
    passes=(VELOCITY, RECONSTRUCT),
    run=run,
    default_grid={"quality": list(twin.SAMPLES_BY_QUALITY)},
    twin=twin.engine_godot,
    doc="Godot's motion blur (pull request godotengine/godot#115027 and its addon), from "
    "its documented design: camera rotation, camera translation and object multipliers with "
    "the clamp to the largest, near-plane correction, depth velocity, frame-rate modes, "
    "Guertin-style tiles and a gather centred on the pixel with 4/8/16 taps. "
    "docs/spec.md §17.10.",
)
