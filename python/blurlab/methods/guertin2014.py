"""reconstruct_guertin2014: the stable filter of Guertin, McGuire and Nowrouzezahrai, "A Fast
and Stable Feature-Aware Motion Blur Filter" (HPG 2014), as changes to docs/spec.md §3
(docs/guertin2014.md): direction-keeping dilation, two sampling directions, mirrored pairs and
alignment weights. Shader shaders/passes/reconstruct_guertin2014.glsl, NumPy twin
blurlab.twins.guertin2014.reconstruct_guertin2014. Parameters: TILE_FILTER_PARAMS,
FILTER_OPTIONS, and the paper's two constants gamma and kappa declared here.
"""

from __future__ import annotations

from ..twins import guertin2014 as twin
from .core import FLOAT32_MAX, Method, Param, Pass, register
from .tile_filter import FILTER_OPTIONS, TILE_FILTER_PARAMS, options_filter, uniform_names

PARAMS = {
    **TILE_FILTER_PARAMS,
    **FILTER_OPTIONS,
    "gamma": Param(
        1.5, float, "γ: px over 0.5 at which wc is V[X]'s direction", 0, FLOAT32_MAX, low_open=True
    ),
    "kappa": Param(
        40.0, float, "κ: center weight S / (κ len(V[X]))", 0, FLOAT32_MAX, low_open=True
    ),
}


RECONSTRUCT = Pass("reconstruct", "passes/reconstruct_guertin2014.glsl", uniform_names(PARAMS))


register(
    Method(
        name="reconstruct_guertin2014",
        **options_filter(
            PARAMS, RECONSTRUCT, diagonal_reach=True, grid={"k": [20], "samples": [9, 15, 25]}
        ),
        twin=twin.reconstruct_guertin2014,
        doc="Guertin, McGuire, Nowrouzezahrai: A Fast and Stable Feature-Aware Motion Blur "
        "Filter (HPG 2014): docs/spec.md §3 with direction-keeping dilation, two sampling "
        "directions, mirrored pairs and alignment weights. docs/guertin2014.md.",
    )
)
