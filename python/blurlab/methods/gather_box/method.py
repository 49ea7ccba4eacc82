"""gather_box ("Blurry things", docs/spec.md §4; spec.md here): n equal taps along the motion,
backward or centered, with the edge rules of "Blurry things" (clamp, ignore, or a guard band
re-rendered around the frame) of blurlab.methods.gathers. Shader gather.glsl here over
shaders/common/box_gather.glsl, which the camera's-motion gather shares with it, as it does the
parameters (gathers.BOX_PARAMS); NumPy twin twin.gather_box.
"""

from __future__ import annotations

from ..core import Pass, shader_beside
from ..folders import Declaration
from ..gathers import BOX_PARAMS, box_instant, box_reach, edge_gather
from .twin import gather_box

GATHER = Pass("gather_box", shader_beside(__file__, "gather.glsl"), tuple(BOX_PARAMS))

METHOD = Declaration(
    name="gather_box",
    order=5,
    **edge_gather(GATHER, BOX_PARAMS, box_reach),
    instant=box_instant,
    default_grid={"taps": [5, 10, 20]},
    twin=gather_box,
    gallery=True,
    doc='"Blurry things": n equal taps along the motion, backward or centered. docs/spec.md §4.',
)
