"""reconstruct_mcguire2012: the reconstruction filter of McGuire, Hennessy, Bukowski and Osman,
"A Reconstruction Filter for Plausible Motion Blur" (I3D 2012), docs/spec.md §3.

TileMax → NeighborMax → reconstruct (shaders/passes/reconstruct_mcguire2012.glsl; on a GPU's
compute backend NeighborMax runs in reconstruct's prologue, docs/spec.md §3.6), with the
engines' options of docs/guertin2014.md and, with classify=True, the tile classification of
docs/classify_and_steps.md. NumPy twin: blurlab.twins.classify.reconstruct (the filter of
blurlab.twins.mcguire2012, classified when asked). Parameters: TILE_FILTER_PARAMS,
FILTER_OPTIONS and CLASSIFY_PARAMS; `blurlab methods` lists them with defaults and ranges.
"""

from __future__ import annotations

from ..twins import classify as twin
from .classification import CLASSIFY_PARAMS
from .core import Method, Pass, register
from .tile_filter import (
    FILTER_OPTIONS,
    OPTIONS_AT_DEFAULT,
    TILE_FILTER_PARAMS,
    run_filter,
    uniform_names,
)

PARAMS = {**TILE_FILTER_PARAMS, **FILTER_OPTIONS, **CLASSIFY_PARAMS}
RECONSTRUCT = Pass(
    "reconstruct",
    "passes/reconstruct_mcguire2012.glsl",
    uniform_names({**TILE_FILTER_PARAMS, **FILTER_OPTIONS}),
)

register(
    Method(
        name="reconstruct_mcguire2012",
        kind="filter",
        instant="center",
        params=PARAMS,
        backends=("compute", "fragment"),
        run=run_filter("reconstruct_mcguire2012", PARAMS, RECONSTRUCT, diagonal_reach=False),
        default_grid=[{"k": [10, 20, 40], "samples": [5, 9, 15, 25]}, *OPTIONS_AT_DEFAULT],
        twin=twin.reconstruct,
        study_curves=("samples", "k"),
        gallery=True,
        doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
        "Blur (I3D 2012). docs/spec.md §3; options in docs/guertin2014.md, classification in "
        "docs/classify_and_steps.md.",
    )
)
