"""What gather_coverage offers beside its run (docs/spec.md §17.6; the method is its folder,
methods/gather_coverage/): its parameters, the alternative layouts of its gather and of its film
filter, which benchmarks time (blurlab.methods.variants), and each pixel's tile lines and tap
plan of §17.6.1 on a frame (tile_lines, tap_plan), which studies, benchmarks and tests read.
"""

from __future__ import annotations

import numpy as np

from ..core.frame import Frame
from ..twins import coverage as twin
from ..twins import film
from ..twins.eevee import EARLY_EXIT, resolve_reach_keys
from . import tiles as tile_lists
from .core import (
    SEED,
    BlurResult,
    Method,
    Param,
    method,
    methods,
    resolve_params,
    twin_keywords,
)
from .tile_filter import TILE_FILTER_PARAMS
from .variants import PassVariants

PARAMS = {
    # 16 samples and 1.5 % tiles: the held-out rule of docs/recommend.md met the bar with them.
    "tile_percent": Param(
        1.5, float, "tile side, % of the image height (at least 8 px)", 0, 100, low_open=True
    ),
    "samples": Param(
        16, int, "taps on each half-shutter (half along the tile, half along X)", 2, 32
    ),
    "max_blur": Param(
        30.0, float, "longest half-motion, % of the image height", 0, 100, low_open=True
    ),
    "soft_z": TILE_FILTER_PARAMS["soft_z"],
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
    "film_filter": Param(
        0.0,
        float,
        "σ of a Gaussian film filter on the result, px (0: none, pixel-centre samples as the "
        "temporal reference; 0.5: Blender EEVEE's at its 1.5 px filter size)",
        0,
        4,
    ),
    "film_through_taps": Param(
        False,
        bool,
        "read the film filter through the gather's colour reads (each tap bilinear at a turning "
        "(±d, ±d) px, d the kernel's variance) instead of a pass after it; film_filter up to "
        f"{film.MAX_TAP_SIGMA:.2f}",
    ),
    # Just enough taps (§17.6.1): each off, or at today's value, by default.
    "tap_spacing": Param(
        0.0,
        float,
        "px of the tile's longer line per tap: a side takes clamp(ceil(longest / tap_spacing), "
        "2, samples) taps (0: samples everywhere)",
        0,
        1000,
    ),
    "early_exit": Param(
        EARLY_EXIT,
        float,
        "px: where the tile's longer line is shorter, X keeps its colour with no tap",
        0,
        1000,
    ),
    "uniform_tolerance": Param(
        0.0,
        float,
        "px: an X whose own trails lie this close to the tile's lines takes a plain gather of "
        "the taps moving as it does (0: off)",
        0,
        1000,
    ),
    "half_res_above": Param(
        0.0,
        float,
        "px: a 2 x 2 quad whose tile line and pixels' half-motions are all longer takes one "
        "gather, at its top-left pixel, in a pass at half resolution (0: off)",
        0,
        1000,
    ),
    "tile_dispatch": tile_lists.TILE_DISPATCH,
}
# The gather's variants (methods/gather_coverage/gather.glsl): every tap reads its colour, or
# only the taps that weigh on a sum do (fewer reads, a branch). Same bits; `blurlab bench layouts`
# --variants times both: on the H100 at 1080p fetch_all was as fast or faster (0.0628 against
# 0.0647 ms on teapot_pass, medians over 15 scenes 0.168 and 0.171, 2026-11-24), so it is the
# default, without the branch.
GATHER_VARIANTS = {"fetch_all": {}, "skip_unweighted": {"GATHER_SKIP_UNWEIGHTED": 1}}
GATHER_LAYOUT = PassVariants("gather", GATHER_VARIANTS, "fetch_all")
# The film filter's layouts (methods/gather_coverage/film_filter.glsl): one pass of (2R + 1)²
# taps; two of 2R + 1 (rows, then columns) with an RGBA32F image between them; or one whose work
# group filters its rows in shared memory, then its columns there. Same kernel, sums in another
# order; `blurlab bench layouts` times them. On the H100 at 1080p, σ = 0.5, teapot_pass:
# 0.113 ms direct, 0.079 separable (two passes), 0.044 separable_shared (2026-11-24).
FILM_VARIANTS = {
    "direct": {},
    "separable": {"FILM_SEPARABLE": 1},
    "separable_shared": {"FILM_SHARED": 1},
}
FILM_LAYOUT = PassVariants("film filter", FILM_VARIANTS, "separable_shared")


def _registered() -> Method:
    """The registered method declared with PARAMS (methods/gather_coverage/method.py), found by
    its parameters: no code outside a method's folder names it."""
    for name in methods():
        m = method(name)
        if m.params.keys() == PARAMS.keys() and all(m.params[k] is p for k, p in PARAMS.items()):
            return m
    raise LookupError("blurlab: no registered method takes the coverage gather's parameters")


def tile_lines(frame: Frame, result: BlurResult | None = None, **params) -> twin.TileLines:
    """§17.6 steps 1–3: each pixel's half-motions and tile lines in `frame` at `params` (the
    NumPy twin's twin.tile_lines), on the tile grid of `result`, a run of gather_coverage on
    `frame` at the same tile parameters, where given (the twin's own otherwise)."""
    values = resolve_params(_registered(), frame, params)
    dilated = None
    if result is not None:
        buffers = result.buffers
        dilated = (
            resolve_reach_keys(buffers["reach_keys"], buffers["tiles"])
            if "reach_keys" in buffers
            else buffers["dilated"]
        ).astype(np.float64)
    keywords = {key: values[key] for key in twin_keywords(twin.tile_lines)}
    return twin.tile_lines(frame.motion_prev, frame.motion_next, dilated=dilated, **keywords)


def tap_plan(
    frame: Frame,
    result: BlurResult | None = None,
    tiles: twin.TileLines | None = None,
    **params,
) -> twin.TapPlan:
    """§17.6.1: the taps each pixel of `frame` reads and the path it takes at `params` (the NumPy
    twin's twin.plan_taps: taps_per_pixel(), fast, half) on `tiles`, tile_lines(frame, result,
    **params) unless given (the lines do not depend on the options of §17.6.1)."""
    values = resolve_params(_registered(), frame, params)
    if tiles is None:
        tiles = tile_lines(frame, result, **params)
    keywords = {key: values[key] for key in twin_keywords(twin.plan_taps)}
    return twin.plan_taps(tiles, **keywords)
