"""The mirrored pair of Guertin, McGuire and Nowrouzezahrai (HPG 2014, docs/spec.md §7.2) in
NumPy float64: the part of that filter's twin that the engines' twins which mirror their taps
share (GLSL: shaders/common/mirrored_pair.glsl). The filter's own twin is
methods/reconstruct_guertin2014/twin.py.
"""

from __future__ import annotations

import numpy as np


def mirror_pair(a1, a2, z1, z2, s1, s2):
    """The mirrored pair (docs/spec.md §7.2): the pair takes the weight of its sample that is
    nearer and moves farther (sample 1's where neither is both); z depths, s speeds."""
    behind, slower = z1 > z2, s2 > s1
    return np.where(behind & slower, a2, a1), np.where(~behind & ~slower, a1, a2)


def mirrored_taps(center: np.ndarray, offset: np.ndarray, h: int, w: int) -> list[tuple]:
    """The (rows, columns) of a mirrored pair's two taps at center ± offset, clamped to an
    h x w image (shaders/common/mirrored_pair.glsl, mirrored_taps)."""
    taps = []
    for sign in (1, -1):
        p = np.floor(center + sign * offset).astype(np.int64)
        taps.append((np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)))
    return taps
