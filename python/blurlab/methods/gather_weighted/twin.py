"""gather_weighted, docs/spec.md §4 (ogldev tutorial 41), in NumPy float64. GPU pass: gather.glsl
beside it; the taps and edge rules it shares with the other gathers: blurlab.twins.gathers."""

from __future__ import annotations

import numpy as np

from ...twins.gathers import gather_taps, tap_centers
from ...twins.inputs import sanitize_motion


def gather_weighted(color, motion, *, edge: str) -> np.ndarray:
    """ogldev tutorial 41: m = M/2; taps X, X - m, X - 2m, X - 3m, weights 0.4, 0.3, 0.2, 0.1."""
    m = sanitize_motion(motion) / 2
    center = tap_centers(*m.shape[:2])
    return gather_taps(color, [center - i * m for i in range(4)], [0.4, 0.3, 0.2, 0.1], edge)
