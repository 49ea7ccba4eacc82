"""gather_weighted (ogldev tutorial 41, docs/spec.md §4; spec.md here): four taps along M/2 with
weights 0.4, 0.3, 0.2, 0.1, with the edge rules of "Blurry things" (clamp, ignore, or a guard
band re-rendered around the frame) of blurlab.methods.gathers. Shader gather.glsl here over
shaders/common/gather.glsl; NumPy twin twin.gather_weighted.
"""

from __future__ import annotations

from ..core import Pass, shader_beside
from ..folders import Declaration
from ..gathers import EDGE_PARAM, edge_gather
from .twin import gather_weighted

PARAMS = {"edge": EDGE_PARAM}
GATHER = Pass("gather_weighted", shader_beside(__file__, "gather.glsl"), ("edge",))

METHOD = Declaration(
    name="gather_weighted",
    order=4,
    **edge_gather(GATHER, PARAMS, lambda values: 1.5),
    instant="close",
    twin=gather_weighted,
    doc="ogldev tutorial 41: taps along M/2 with weights 0.4/0.3/0.2/0.1. docs/spec.md §4.",
)
