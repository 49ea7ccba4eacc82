"""Frames whose tiles tie, for the tests of the tile passes' picks (blurlab.methods.eevee's
flatten and dilation, gathered or scattered): equal lengths must go to the first candidate in
row-major order on any device."""

from __future__ import annotations

import numpy as np

import blurlab as bl

# Half-motions whose squared lengths are exact in float32, so that equal lengths are equal on
# any device however it rounds sqrt: 0, 5 and 10 px (scaled by the test), in several directions.
TIED = np.array(
    [(0, 0), (-0.0, 0), (0, -0.0), (3, 4), (4, -3), (-5, 0), (0, 5), (6, 8), (-8, 6), (10, 0)],
    np.float32,
)


def tied_frame(rng, width: int, height: int, scale: float) -> bl.Frame:
    """A frame whose two half-motions are drawn from TIED · scale: most tiles hold several
    candidates of the longest length, and most tiles' sources tie too."""
    halves = [
        TIED[rng.integers(0, len(TIED), (height, width))] * np.float32(scale) for _ in range(2)
    ]
    color = rng.random((height, width, 4), dtype=np.float32)
    depth = rng.uniform(1.0, 10.0, (height, width)).astype(np.float32)
    return bl.Frame(
        color, depth, halves[0] + halves[1], motion_prev=halves[0], motion_next=halves[1]
    )


# Sizes the tile side does not divide; tiles smaller than a work group (4 px: 16 pixels for 64
# threads) and larger (11 and 32 px); reaches of a few sources and of many per thread (r = 11).
CASES = [
    ((100, 60), 8, 40.0, 4.0),
    ((97, 61), 11, 60.0, 3.0),
    ((45, 30), 4, 40.0, 1.0),
    ((150, 90), 32, 64.0, 6.0),
]
