"""stochastic (docs/spec.md §4, the OGRE paper) in NumPy: slice times, the rotated grid, the
per-pixel slice choice, and the combination of the jittered slice renders. GPU twin:
combine.comp beside it, whose header gives the rule."""

from __future__ import annotations

import numpy as np

from ...twins.hashing import pcg, rand
from ...twins.inputs import sanitize_color

# Rotated-grid sample positions inside a pixel, from its top-left corner (pixels).
ROTATED_GRID = np.array([[0.375, 0.125], [0.875, 0.375], [0.125, 0.625], [0.625, 0.875]])
# Neighbour n (below, left, right, above) gives its sample n.
NEIGHBOURS = np.array([[0, 1], [-1, 0], [1, 0], [0, -1]])


def slice_times(shutter, slices: int, seed: int) -> np.ndarray:
    """Slice l at a hashed time in [t0 + l/K·Δ, t0 + (l+1)/K·Δ)."""
    t0, t1 = shutter
    index = np.arange(slices)
    return t0 + (index + rand(index, 1, seed)) / slices * (t1 - t0)


def slice_of(x: np.ndarray, y: np.ndarray, i: int, slices: int, seed: int) -> np.ndarray:
    """The slice sample i of pixel (x, y) takes: quarter q = π(i) of a hashed permutation of
    0..3 (Lehmer code h mod 24), then floor((q + r)·K/4) with r hashed per (pixel, i)."""
    x = np.asarray(x, np.uint32)
    shape = x.shape
    with np.errstate(over="ignore"):
        h = pcg(x.ravel() ^ pcg(np.asarray(y, np.uint32).ravel() ^ pcg(np.uint32(seed))))
        order = np.tile(np.arange(4), (h.size, 1))
        rows = np.arange(h.size)
        code = h % np.uint32(24)
        for k in range(3):
            j = k + (code % np.uint32(4 - k)).astype(np.int64)
            code = code // np.uint32(4 - k)
            a, b = order[rows, k].copy(), order[rows, j].copy()
            order[rows, k], order[rows, j] = b, a
        r = (pcg(h ^ np.uint32(i + 1)) >> np.uint32(8)).astype(np.float64) / 2.0**24
    chosen = np.floor((order[:, i] + r) * slices / 4).astype(np.int64)
    return np.minimum(chosen, slices - 1).reshape(shape)


def combine(renders: np.ndarray, slices: int, seed: int) -> np.ndarray:
    """renders: (K, 4, H, W, C), render of slice l at grid position i. C = 5/32 Σ inside +
    3/32 Σ neighbour samples."""
    renders = sanitize_color(renders)
    h, w = renders.shape[2:4]
    y, x = np.mgrid[0:h, 0:w]
    out = np.zeros(renders.shape[2:])
    for i in range(4):
        own = slice_of(x, y, i, slices, seed)
        out += 5 / 32 * renders[own, i, y, x]
        nx = np.clip(x + NEIGHBOURS[i, 0], 0, w - 1)
        ny = np.clip(y + NEIGHBOURS[i, 1], 0, h - 1)
        theirs = slice_of(nx, ny, i, slices, seed)
        out += 3 / 32 * renders[theirs, i, ny, nx]
    return out
