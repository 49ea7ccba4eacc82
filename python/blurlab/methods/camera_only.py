"""camera_only (Urho3D thesis §2.3.2): motion from depth and the camera's t0/t1 transforms
alone (shaders/passes/camera_motion.glsl, NumPy twin blurlab.twins.gathers.camera_motion),
then gather_box with gather_box's parameters; moving objects get no blur of their own.
docs/spec.md §4.
"""

from __future__ import annotations

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..core.render import camera_matrices
from .core import Method, Pass, PassRunner, register
from .gathers import BOX_PARAMS, GATHER_BOX, box_instant, box_reach, with_edge


def camera_motion_uniforms(camera: dict) -> dict:
    """The uniforms of the camera-motion pass from a rendered frame's camera matrices."""
    return {
        "view_from_clip": np.linalg.inv(camera["projection"]).astype(np.float32),
        "world_from_view": np.linalg.inv(camera["view"][2]).astype(np.float32),
        "clip_from_world": camera["view_projection"][:2].astype(np.float32),
        "sky_from_clip": camera["sky_from_clip"].astype(np.float32),
        "sky_projection": camera["sky_projection"].astype(np.float32),
        "near": float(camera["near"]),
    }


# What a pass that splits the camera's motion off reads for a frame made from arrays, which has
# no camera: has_camera = False, and the matrices (unread then) that GL still wants set.
_NO_CAMERA = {
    "view_from_clip": np.eye(4, dtype=np.float32),
    "world_from_view": np.eye(4, dtype=np.float32),
    "clip_from_world": np.stack([np.eye(4, dtype=np.float32)] * 2),
    "sky_from_clip": np.eye(4, dtype=np.float32),
    "sky_projection": np.stack([np.eye(4, dtype=np.float32)] * 2),
    "near": 1.0,
    "has_camera": False,
}


def split_camera_uniforms(camera: dict | None) -> dict:
    """The uniforms of a pass that splits the camera's part off a frame's motion
    (common/camera_motion.glsl and `has_camera`), from the frame's camera matrices or None."""
    if camera is None:
        return _NO_CAMERA
    return {**camera_motion_uniforms(camera), "has_camera": True}


# Motion from depth and the camera's transforms; a compute pass whatever the gather's backend.
CAMERA_MOTION = Pass("camera_motion", "passes/camera_motion.glsl")


def _run_camera_only(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
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
        passes = PassRunner(ctx, BOX_PARAMS, values)
        uniforms = camera_motion_uniforms(camera)
        passes.run(
            CAMERA_MOTION, {"depth": textures["depth"]}, {"motion": motion}, uniforms=uniforms
        )
        gathered = {"color": textures["color"], "motion": motion}
        result = passes.run_result(GATHER_BOX, gathered, backend)
        ctx.recycle(motion)
        return result, passes.timings

    color, timings = with_edge(ctx, frame, inputs, values["edge"], box_reach(values), on)
    return {"color": color}, timings


register(
    Method(
        name="camera_only",
        kind="gather",
        instant=box_instant,
        params=BOX_PARAMS,
        backends=("compute", "fragment"),
        run=_run_camera_only,
        default_grid={"taps": [10]},
        gallery=True,
        doc="Urho3D thesis §2.3.2: motion from depth and the camera's transforms alone, then "
        "gather_box; moving objects get no blur of their own. docs/spec.md §4.",
    )
)
