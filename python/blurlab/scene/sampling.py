"""Low-discrepancy samples for the antialiased reference (docs/spec.md §11 "Antialiased"):
the first three dimensions of the Sobol sequence, each Owen-scrambled with a hashed nested
uniform scramble (Burley 2020, "Practical Hash-based Owen Scrambling"), in NumPy."""

from __future__ import annotations

import numpy as np

from ..twins.hashing import pcg

BITS = 32

# Joe and Kuo's primitive polynomials and initial direction numbers for Sobol dimensions 2 and
# 3 (degree s, coefficient bits a, initial m_1 ... m_s); dimension 1 is the van der Corput
# sequence.
POLYNOMIALS = ((1, 0, (1,)), (2, 1, (1, 3)))
DIMENSIONS = 1 + len(POLYNOMIALS)


def direction_numbers(dimension: int) -> np.ndarray:
    """The 32 direction numbers v_k (uint32, bit k of the index XORs in v_k)."""
    if dimension == 0:
        return np.array([1 << (BITS - 1 - k) for k in range(BITS)], dtype=np.uint32)
    degree, coefficients, initial = POLYNOMIALS[dimension - 1]
    m = list(initial)
    for k in range(degree, BITS):
        value = m[k - degree] ^ (m[k - degree] << degree)
        for j in range(1, degree):
            if (coefficients >> (degree - 1 - j)) & 1:
                value ^= m[k - j] << j
        m.append(value)
    return np.array([m[k] << (BITS - 1 - k) for k in range(BITS)], dtype=np.uint32)


def sobol(index: np.ndarray, dimension: int) -> np.ndarray:
    """Unscrambled Sobol points (uint32 fixed point in [0, 1)) of the given indices."""
    index = np.asarray(index, dtype=np.uint32)
    result = np.zeros_like(index)
    for k, v in enumerate(direction_numbers(dimension)):
        result ^= np.where((index >> np.uint32(k)) & np.uint32(1), v, np.uint32(0))
    return result


def reverse_bits(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.uint32)
    out = np.zeros_like(x)
    for k in range(BITS):
        out |= ((x >> np.uint32(k)) & np.uint32(1)) << np.uint32(BITS - 1 - k)
    return out


def owen_scramble(x: np.ndarray, seed) -> np.ndarray:
    """Nested uniform (Owen) scramble of uint32 fixed-point values: each bit is flipped by a
    hash of the bits above it and the seed (Laine and Karras' permutation on reversed bits)."""
    with np.errstate(over="ignore"):
        x = reverse_bits(x) + np.uint32(seed)
        for constant in (0x6C50B47C, 0xB82F1E52, 0xC7AFE638, 0x8D22F6E6):
            x ^= x * np.uint32(constant)
    return reverse_bits(x)


def scrambled_sobol(samples: int, seed: int) -> np.ndarray:
    """(samples, 3) float64 points in [0, 1)^3: Sobol indices 0 ... N - 1, every dimension
    scrambled with its own hashed seed. For N = 2^m, dimensions 0 and 1 form a (0, m, 2)-net
    (one point in every 2^-j x 2^-(m-j) box), each dimension alone has one point in each of the
    N strata of [0, 1), and the three together are a (1, m, 3)-net."""
    index = np.arange(samples, dtype=np.uint32)
    columns = []
    for dimension in range(DIMENSIONS):
        dimension_seed = pcg(np.uint32(seed) ^ pcg(np.uint32(dimension + 0x9E37)))
        columns.append(owen_scramble(sobol(index, dimension), dimension_seed))
    return np.stack(columns, axis=1).astype(np.float64) / 2.0**BITS


def shutter_samples(shutter, samples: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(times, positions) of the antialiased reference, in time order: times in the shutter,
    positions (N, 2) inside the pixel measured from its top-left corner.

    Positions are scrambled Sobol dimensions 0 and 1 (the best-spread pair: still edges see a
    (0, m, 2)-net), the time dimension 2. For N not a power of two the k-th earliest time is
    then moved into [k/N, (k+1)/N), keeping its offset in the stratum: every stratum holds one
    time, as in the temporal reference; powers of two are left unchanged."""
    points = scrambled_sobol(samples, seed)
    points = points[np.argsort(points[:, 2], kind="stable")]
    scaled = points[:, 2] * samples
    u = (np.arange(samples) + (scaled - np.floor(scaled))) / samples
    t0, t1 = shutter
    return t0 + u * (t1 - t0), points[:, :2]
