"""gather_gaussian: n taps along the motion, centered on the pixel, with Gaussian weights
exp(-s² / 2σ²) where s ∈ [-1/2, 1/2] is the tap's position in motion lengths (docs/spec.md
§4; spec.md here). A smoother falloff than the box gather's equal weights, for the same taps.
Shader gather.glsl here, NumPy twin twin.gather_gaussian, test test_gather_gaussian.py.
"""

from __future__ import annotations

from ..core import Param, Pass, shader_beside
from ..folders import Declaration
from ..gathers import EDGE_PARAM, edge_gather
from .twin import gather_gaussian

PARAMS = {
    "taps": Param(9, int, "n taps along the motion, centered on the pixel", 2, 256),
    # Below 0.05 the weights of an even n underflow float32 (exp(-50) is the smallest kept).
    "sigma": Param(0.25, float, "σ of the weights, a fraction of the motion's length", 0.05, 10),
    "edge": EDGE_PARAM,
}
GATHER = Pass("gather_gaussian", shader_beside(__file__, "gather.glsl"), tuple(PARAMS))

METHOD = Declaration(
    name="gather_gaussian",
    order=10,
    **edge_gather(GATHER, PARAMS, reach=lambda values: 0.5),
    default_grid={"taps": [5, 9, 17], "sigma": [0.25]},
    twin=gather_gaussian,
    doc="n taps along the motion around the pixel, weighted exp(-s²/2σ²). docs/spec.md §4.",
)
