"""reconstruct_mcguire2012: the reconstruction filter of McGuire, Hennessy, Bukowski and Osman,
"A Reconstruction Filter for Plausible Motion Blur" (I3D 2012), docs/spec.md §3.

TileMax → NeighborMax → reconstruct (shaders/passes/reconstruct_mcguire2012.glsl), with the
engines' options of docs/guertin2014.md. NumPy twin:
blurlab.twins.mcguire2012.reconstruct_mcguire2012. Parameters: TILE_FILTER_PARAMS and
FILTER_OPTIONS; `blurlab methods` lists them with defaults and ranges. Tile classification was
built as an option and removed: it measured slower (docs/classify_and_steps.md).
"""

from __future__ import annotations

from ..twins import mcguire2012 as twin
from .core import Method, Pass, register
from .tile_filter import FILTER_OPTIONS, TILE_FILTER_PARAMS, options_filter, uniform_names

PARAMS = {**TILE_FILTER_PARAMS, **FILTER_OPTIONS}
RECONSTRUCT = Pass("reconstruct", "passes/reconstruct_mcguire2012.glsl", uniform_names(PARAMS))

register(
    Method(
        name="reconstruct_mcguire2012",
        **options_filter(
            PARAMS,
            RECONSTRUCT,
            diagonal_reach=False,
            grid={"k": [10, 20, 40], "samples": [5, 9, 15, 25]},
        ),
        twin=twin.reconstruct_mcguire2012,
        study_curves=("samples", "k"),
        gallery=True,
        example=True,
        doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
        "Blur (I3D 2012). docs/spec.md §3; options in docs/guertin2014.md.",
    )
)
