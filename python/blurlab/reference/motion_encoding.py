"""Motion storage formats, SPEC.md §2, in NumPy (GPU twin: shaders/passes/motion_encoding.comp).

Each function returns the motion a method reading that format sees: encode, round to the
format's precision, decode. 8-bit channels round to the nearest of 256 levels, as GL's
float-to-unorm conversion does.
"""

from __future__ import annotations

import numpy as np


def _unorm8(c: np.ndarray) -> np.ndarray:
    return np.round(np.clip(c, 0.0, 1.0) * 255.0) / 255.0


def rg32f(m: np.ndarray, maxlen: float) -> np.ndarray:
    return np.asarray(m, dtype=np.float32).astype(np.float64)


def rg16f(m: np.ndarray, maxlen: float) -> np.ndarray:
    return np.asarray(m, dtype=np.float32).astype(np.float16).astype(np.float64)


def rgba8_offset(m: np.ndarray, maxlen: float) -> np.ndarray:
    c = _unorm8(np.clip(np.asarray(m, np.float64) / maxlen, -1.0, 1.0) * 0.5 + 0.5)
    return (c * 2.0 - 1.0) * maxlen


def rgba8_polar(m: np.ndarray, maxlen: float) -> np.ndarray:
    m = np.asarray(m, np.float64)
    length = np.linalg.norm(m, axis=-1, keepdims=True)
    direction = np.where(length > 0, m / np.where(length > 0, length, 1.0), 0.0)
    rg = _unorm8(direction * 0.5 + 0.5)
    b = _unorm8(np.sqrt(np.minimum(length / maxlen, 1.0)))
    return (rg * 2.0 - 1.0) * b * b * maxlen


DECODED = {"rg32f": rg32f, "rg16f": rg16f, "rgba8_offset": rgba8_offset, "rgba8_polar": rgba8_polar}


def decoded(m: np.ndarray, motion_format: str, maxlen: float) -> np.ndarray:
    """The motion a method reading `motion_format` sees, float64."""
    return DECODED[motion_format](m, maxlen)
