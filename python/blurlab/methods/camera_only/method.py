"""camera_only (Urho3D thesis §2.3.2; docs/spec.md §4, spec.md here): motion from depth and the
camera's t0/t1 transforms alone (camera_motion.glsl here over shaders/common/camera_motion.glsl,
NumPy twin blurlab.twins.gathers.camera_motion), then the box gather of "Blurry things" with
its parameters (gather.glsl here over shaders/common/box_gather.glsl, blurlab.methods.gathers);
moving objects get no blur of their own. Twin: twin.camera_only, which takes the camera's
matrices, so the method declares none of the frame's arrays alone.
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...core.render import camera_matrices
from ..camera_motion import camera_motion_uniforms
from ..core import Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..gathers import BOX_PARAMS, box_instant, box_reach, with_edge

# Motion from depth and the camera's transforms; a compute pass whatever the gather's backend.
CAMERA_MOTION = Pass("camera_motion", shader_beside(__file__, "camera_motion.glsl"))
GATHER = Pass("gather", shader_beside(__file__, "gather.glsl"), tuple(BOX_PARAMS))


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    if frame.camera is None:
        raise ValueError(
            "blurlab: camera_only needs the camera's transforms: use a frame made by ctx.render"
        )

    def on(textures):
        height, width = textures["color"].shape[:2]
        guard = (width - frame.size[0]) // 2
        camera = frame.camera
        if guard:  # the margin's frustum, as render_targets widened it
            camera = camera_matrices(frame.scene, frame.size, tuple(camera["times"]), guard)
        motion = ctx.pooled((height, width, 2))
        runner = PassRunner(ctx, BOX_PARAMS, values)
        uniforms = camera_motion_uniforms(camera)
        runner.run(
            passes[CAMERA_MOTION.name],
            {"depth": textures["depth"]},
            {"motion": motion},
            uniforms=uniforms,
        )
        gathered = {"color": textures["color"], "motion": motion}
        result = runner.run_result(passes[GATHER.name], gathered, backend)
        ctx.recycle(motion)
        return result, runner.timings

    color, timings = with_edge(ctx, frame, inputs, values["edge"], box_reach(values), on)
    return {"color": color}, timings


METHOD = Declaration(
    name="camera_only",
    kind="gather",
    order=6,
    instant=box_instant,
    params=BOX_PARAMS,
    passes=(CAMERA_MOTION, GATHER),
    backends=("compute", "fragment"),
    run=run,
    default_grid={"taps": [10]},
    gallery=True,
    doc="Urho3D thesis §2.3.2: motion from depth and the camera's transforms alone, then "
    'the box gather of "Blurry things"; moving objects get no blur of their own. '
    "docs/spec.md §4.",
)
