"""The converged reference over a shutter, docs/spec.md §1, in NumPy: sample times and the mean.
GPU twin: shaders/passes/accumulate.comp driven by blurlab.core.references.reference_render."""

from __future__ import annotations

import numpy as np

from .hashing import rand
from .inputs import sanitize_color


def sample_times(
    shutter: tuple[float, float], samples: int, stratified: bool, seed: int
) -> np.ndarray:
    """t_i = t0 + (i + u_i)/N · (t1 - t0): u_i = 0.5, or rand(i, 0, seed) when stratified."""
    t0, t1 = shutter
    i = np.arange(samples)
    u = rand(i, 0, seed) if stratified else np.full(samples, 0.5)
    return t0 + (i + u) / samples * (t1 - t0)


def mean_of_renders(colors) -> np.ndarray:
    """The reference: the mean of the sub-frame colors, float64."""
    return np.mean(sanitize_color(colors), axis=0)
