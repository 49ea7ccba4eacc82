"""What Unreal Engine 4's and 5's motion blurs share (docs/spec.md §17.5, §17.7): the
parameters of engine_unreal, which engine_unreal5 and gather_pixel take up, and the velocity
flatten into the 11:11:10 polar texel (shaders/passes/unreal_velocity_flatten.glsl), the first
pass of both engines. Each method is its folder (methods/engine_unreal/,
methods/engine_unreal5/); the passes' NumPy twins are blurlab.twins.unreal.
"""

from __future__ import annotations

from .core import FLOAT32_MAX, SEED, Param, Pass
from .tile_filter import TILE_FILTER_PARAMS

PARAMS = {
    "quality": Param(3, int, "r.MotionBlurQuality: 4, 6, 8 or 16 samples", 1, 4),
    "max_blur": Param(
        5.0, float, "Unreal's Max: longest blur radius, % of the image width", 0, 100, low_open=True
    ),
    "depth_extent": Param(
        1.0, float, "soft depth extent, depth units", 0, FLOAT32_MAX, low_open=True
    ),
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
}
FLATTEN = Pass("velocity_flatten", "passes/unreal_velocity_flatten.glsl", ("exposure",))
