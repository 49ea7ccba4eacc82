"""NumPy twin of shaders/util/test_pattern.comp."""

from __future__ import annotations

import numpy as np

from .hashing import rand


def test_pattern(width: int, height: int, seed: int = 0, checker: int = 16) -> np.ndarray:
    """(H, W, 4) float64: u and v of the pixel center, a checkerboard, rand(x, y, seed)."""
    y, x = np.mgrid[0:height, 0:width]
    u = (x + 0.5) / width
    v = (y + 0.5) / height
    board = ((x // checker + y // checker) % 2).astype(np.float64)
    return np.stack([u, v, board, rand(x, y, seed)], axis=-1)


test_pattern.__test__ = False  # not a pytest test, despite its name
