"""reconstruct_guertin2014: the stable filter of Guertin, McGuire and Nowrouzezahrai, "A Fast
and Stable Feature-Aware Motion Blur Filter" (HPG 2014), as changes to docs/spec.md §3
(docs/guertin2014.md; docs/spec.md §7, spec.md here): direction-keeping dilation, two sampling
directions, mirrored pairs and alignment weights. Shader reconstruct.glsl beside this file,
NumPy twin twin.reconstruct_guertin2014. Parameters: TILE_FILTER_PARAMS, FILTER_OPTIONS
(blurlab/methods/tile_filter.py), and the paper's two constants gamma and kappa declared here.
"""

from __future__ import annotations

from ..core import FLOAT32_MAX, Param, Pass, shader_beside
from ..folders import Declaration
from ..tile_filter import FILTER_OPTIONS, TILE_FILTER_PARAMS, options_filter, uniform_names
from .twin import reconstruct_guertin2014

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


RECONSTRUCT = Pass(
    "reconstruct", shader_beside(__file__, "reconstruct.glsl"), uniform_names(PARAMS)
)


METHOD = Declaration(
    name="reconstruct_guertin2014",
    order=2,
    **options_filter(
        PARAMS, RECONSTRUCT, diagonal_reach=True, grid={"k": [20], "samples": [9, 15, 25]}
    ),
    twin=reconstruct_guertin2014,
    doc="Guertin, McGuire, Nowrouzezahrai: A Fast and Stable Feature-Aware Motion Blur "
    "Filter (HPG 2014): docs/spec.md §3 with direction-keeping dilation, two sampling "
    "directions, mirrored pairs and alignment weights. docs/guertin2014.md.",
)
