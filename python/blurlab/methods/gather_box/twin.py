"""gather_box, docs/spec.md §4 ("Blurry things"), in NumPy float64: the box gather of
blurlab.twins.gathers along the G-buffer's motion. GPU pass: gather.glsl beside it."""

from __future__ import annotations

import numpy as np

from ...twins.gathers import box_gather


def gather_box(
    color, motion, *, taps: int, intensity: float, direction: str, edge: str
) -> np.ndarray:
    """n equal taps at X - s·M·intensity, s = i/(n-1), minus 1/2 for direction "centered"."""
    return box_gather(color, motion, taps=taps, intensity=intensity, direction=direction, edge=edge)
