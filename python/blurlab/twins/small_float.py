"""Unsigned small floats, as the packed B10G11R11 texture format holds them (docs/spec.md
§17.4), in NumPy (GLSL twin: shaders/common/small_float.glsl).

Both kinds have a 5-bit exponent (bias 15) and no sign; the 11-bit one keeps 6 mantissa bits,
the 10-bit one 5. `quantize` rounds a float32 to the nearest such value (ties to an even
mantissa), on the float32 bits themselves, so that the GPU and NumPy round alike: a value beyond
the largest finite one becomes that one, +inf stays +inf, zero, negatives and NaN become 0.
Values below 2^-14 become denormals, multiples of 2^-(14 + m).
"""

from __future__ import annotations

import numpy as np

UF11_MANTISSA = 6
UF10_MANTISSA = 5
SMALLEST_NORMAL = 2.0**-14


def largest_finite(mantissa_bits: int) -> float:
    """2^15·(2 - 2^-m): 65024 for the 11-bit kind, 64512 for the 10-bit one."""
    return 2.0**15 * (2.0 - 2.0**-mantissa_bits)


def quantize(x, mantissa_bits: int) -> np.ndarray:
    """x (rounded to float32 first, as the GPU holds it) as the nearest unsigned float with a
    5-bit exponent and `mantissa_bits` mantissa bits, float64."""
    x = np.asarray(x, np.float32)
    drop = 23 - mantissa_bits
    bits = x.view(np.uint32).astype(np.uint64)
    half = np.uint64((1 << (drop - 1)) - 1)
    odd = (bits >> np.uint64(drop)) & np.uint64(1)
    rounded = ((bits + half + odd) >> np.uint64(drop)) << np.uint64(drop)
    normal = rounded.astype(np.uint32).view(np.float32).astype(np.float64)
    normal = np.minimum(normal, largest_finite(mantissa_bits))
    scale = 2.0 ** (14 + mantissa_bits)
    denormal = np.round(x.astype(np.float64) * scale) / scale  # numpy rounds half to even
    value = np.where(x < SMALLEST_NORMAL, denormal, normal)
    value = np.where(np.isposinf(x), np.inf, value)
    return np.where((x > 0) & ~np.isnan(x), value, 0.0)
