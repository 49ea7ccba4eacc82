"""Whether a tile's motion reaches another tile, docs/spec.md §17.2 step 2 and §17.5 step 3, in
NumPy (GPU twin: shaders/common/tile_reach.glsl): the motion's segment, in tile units, meets the
other tile's square widened by h + REACH_MARGIN, h = 1/2 - 1/(2s), how far a tile's pixel
centers lie from its center. Shared by engine_eevee's dilation and engine_unreal's 7 x 7
neighbourhood.
"""

from __future__ import annotations

import numpy as np

REACH_MARGIN = 0.01  # tiles added around a tile's reach: conservative against rounding


def reach_widening(tile_size: int) -> float:
    """h + REACH_MARGIN for tiles of `tile_size` pixels."""
    return 0.5 - 0.5 / tile_size + REACH_MARGIN


def segment_meets_box(start, direction, low: float, high: float) -> np.ndarray:
    """Whether the segment start + t·direction, t in [0, 1], meets the square [low, high]²
    (the slab test; a zero component must lie inside its slab)."""
    t_min = np.zeros(start.shape[:-1])
    t_max = np.ones(start.shape[:-1])
    inside = np.ones(start.shape[:-1], bool)
    for axis in (0, 1):
        p, d = start[..., axis], direction[..., axis]
        flat = d == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (low - p) / d
            t2 = (high - p) / d
        t_min = np.where(flat, t_min, np.maximum(t_min, np.minimum(t1, t2)))
        t_max = np.where(flat, t_max, np.minimum(t_max, np.maximum(t1, t2)))
        inside &= ~flat | ((p >= low) & (p <= high))
    return inside & (t_min <= t_max)
