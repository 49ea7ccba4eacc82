"""Motion storage formats, docs/spec.md §2, in NumPy (GPU twin:
shaders/passes/motion_encoding.comp).

`decoded` returns the motion a method reading a format sees: encode, round to the format's
precision, decode. The encoding is computed in float32, as the GPU computes it, so that values
that land exactly between two 8-bit levels land there in both.

GL lets the float-to-unorm conversion return either of the two nearest levels ("rounding to
nearest is preferred", GL 4.5 §2.3.5): llvmpipe rounds to nearest, the H100 driver does not
always. `decoded_allowed` lists every result the rule permits, for tests.
"""

from __future__ import annotations

import itertools

import numpy as np


def _offset_levels(m: np.ndarray, maxlen: float) -> np.ndarray:
    """rgba8_offset: c·255 per channel before rounding, float32."""
    m = np.asarray(m, np.float32)
    c = np.clip(m / np.float32(maxlen), -1, 1) * np.float32(0.5) + np.float32(0.5)
    return c * np.float32(255)


def _polar_levels(m: np.ndarray, maxlen: float) -> np.ndarray:
    """rgba8_polar: (R, G, B)·255 before rounding, float32."""
    m = np.asarray(m, np.float32)
    length = np.sqrt(np.sum(m * m, axis=-1, keepdims=True))
    safe = np.where(length > 0, length, np.float32(1))
    direction = np.where(length > 0, m / safe, np.float32(0))
    b = np.sqrt(np.minimum(length / np.float32(maxlen), np.float32(1)))
    return np.concatenate([direction * np.float32(0.5) + np.float32(0.5), b], -1) * np.float32(255)


def _decode_offset(levels: np.ndarray, maxlen: float) -> np.ndarray:
    """M = (c·2 - 1)·maxlen, levels 127 and 128 read as zero: 0.5 is not an 8-bit level, and
    without this a still pixel would move by half a quantization step."""
    m = (levels / 255.0 * 2.0 - 1.0) * maxlen
    return np.where((levels == 127) | (levels == 128), 0.0, m)


def _decode_polar(levels: np.ndarray, maxlen: float) -> np.ndarray:
    b = levels[..., 2:3] / 255.0
    return (levels[..., :2] / 255.0 * 2.0 - 1.0) * b * b * maxlen


_LEVELS = {
    "rgba8_offset": (_offset_levels, _decode_offset),
    "rgba8_polar": (_polar_levels, _decode_polar),
}


def decoded(m: np.ndarray, motion_format: str, maxlen: float) -> np.ndarray:
    """The motion a method reading `motion_format` sees (8-bit levels rounded to nearest,
    ties up), float64."""
    m = np.asarray(m)
    if motion_format == "rg32f":
        return m.astype(np.float32).astype(np.float64)
    if motion_format == "rg16f":
        return m.astype(np.float32).astype(np.float16).astype(np.float64)
    encode, decode = _LEVELS[motion_format]
    return decode(np.floor(encode(m, maxlen).astype(np.float64) + 0.5), maxlen)


def decoded_allowed(m: np.ndarray, motion_format: str, maxlen: float) -> np.ndarray:
    """(K, ..., 2): every decoded motion GL's conversion rule permits (each 8-bit channel
    rounded down or up). For rg32f and rg16f, K = 1 and the value of `decoded`."""
    if motion_format not in _LEVELS:
        return decoded(m, motion_format, maxlen)[None]
    encode, decode = _LEVELS[motion_format]
    exact = np.clip(encode(m, maxlen).astype(np.float64), 0, 255)
    channels = exact.shape[-1]
    choices = []
    for ups in itertools.product((False, True), repeat=channels):
        levels = np.where(np.array(ups), np.ceil(exact), np.floor(exact))
        choices.append(decode(levels, maxlen))
    return np.stack(choices)
