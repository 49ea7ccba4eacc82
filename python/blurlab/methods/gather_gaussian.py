"""gather_gaussian: n taps along the motion, centered on the pixel, with Gaussian weights
exp(-s² / 2σ²) where s ∈ [-1/2, 1/2] is the tap's position in motion lengths (docs/spec.md
§4). A smoother falloff than gather_box's equal weights, for the same taps. Shader
shaders/passes/gather_gaussian.glsl, NumPy twin blurlab.twins.gathers.gather_gaussian,
test tests/test_gather_gaussian.py.
"""

from __future__ import annotations

from ..twins import gathers as twin
from .core import Method, Param, Pass, register
from .gathers import EDGE_PARAM, edge_gather

PARAMS = {
    "taps": Param(9, int, "n taps along the motion, centered on the pixel", 2, 256),
    # Below 0.05 the weights of an even n underflow float32 (exp(-50) is the smallest kept).
    "sigma": Param(0.25, float, "σ of the weights, a fraction of the motion's length", 0.05, 10),
    "edge": EDGE_PARAM,
}
GATHER = Pass("gather_gaussian", "passes/gather_gaussian.glsl", tuple(PARAMS))

register(
    Method(
        name="gather_gaussian",
        **edge_gather(GATHER, PARAMS, reach=lambda values: 0.5),
        default_grid={"taps": [5, 9, 17], "sigma": [0.25]},
        twin=twin.gather_gaussian,
        doc="n taps along the motion around the pixel, weighted exp(-s²/2σ²). docs/spec.md §4.",
    )
)
