"""gather_gaussian, docs/spec.md §4, in NumPy float64. GPU pass: gather.glsl beside it; the taps
and edge rules it shares with the other gathers: blurlab.twins.gathers."""

from __future__ import annotations

import numpy as np

from ...twins.gathers import gather_taps, tap_centers
from ...twins.inputs import sanitize_motion


def gather_gaussian(color, motion, *, taps: int, sigma: float, edge: str) -> np.ndarray:
    """n taps at X - s·M, s = i/(n-1) - 1/2, weighted exp(-s² / 2σ²) (σ in motion lengths)."""
    m = sanitize_motion(motion)
    center = tap_centers(*m.shape[:2])
    s = np.arange(taps) / (taps - 1) - 0.5
    weights = np.exp(-(s**2) / (2 * sigma**2))
    return gather_taps(color, [center - si * m for si in s], list(weights), edge)
