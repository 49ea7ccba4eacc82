"""reconstruct_guertin2014 in NumPy float64: Guertin, McGuire and Nowrouzezahrai, "A Fast and
Stable Feature-Aware Motion Blur Filter" (HPG 2014), as changes to docs/spec.md §3
(docs/guertin2014.md lists them, numbered as below; spec.md here). GPU pass: reconstruct.glsl
beside it, after TileMax (§3.2) and NeighborMax with diagonal_reach (step 1,
blurlab.twins.mcguire2012.neighbor_max)."""

from __future__ import annotations

import numpy as np

from ...twins.guertin2014 import mirror_pair, mirrored_taps
from ...twins.hashing import rand
from ...twins.inputs import round_to_half
from ...twins.mcguire2012 import cone, cylinder, filter_start, len_half, soft_depth_compare


def _direction(v: np.ndarray) -> np.ndarray:
    """v / |v|, or 0 where v = 0."""
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.where(length > 0, v / np.where(length > 0, length, 1.0), 0.0)


def center_direction(vn: np.ndarray, vx: np.ndarray, gamma: float) -> np.ndarray:
    """Step 2, the paper's Eq. 1: wc = normalize(lerp(wp, V[X]/|V[X]|, clamp((|V[X]| - 0.5) / γ,
    0, 1))), wp = vN's perpendicular on V[X]'s side (where V[X] = 0: wp)."""
    wn = _direction(vn)
    wp = np.stack([-wn[..., 1], wn[..., 0]], -1)
    vx_length = np.linalg.norm(vx, axis=-1)
    # Side of V[X]; where V[X] is parallel to vN (within 1e-3 rad) the left perpendicular, so
    # that float rounding does not pick the side.
    wp = np.where((np.sum(wp * vx, -1) < -1e-3 * vx_length)[..., None], -wp, wp)
    blend = np.clip((vx_length - 0.5) / gamma, 0, 1)[..., None]
    own = np.where((vx_length > 0)[..., None], _direction(vx), wp)
    return _direction(wp + (own - wp) * blend)


def sample_weight(x, y, px, py, depth, v, vx, wc, d, soft_z) -> np.ndarray:
    """Step 4: docs/spec.md §3.4's three terms, the sample's cone scaled by wb = |V̂[Y]·d|, the
    center's by wa = |wc·d|, the cylinder (of the shorter motion) by max(wa, wb)."""
    dist = np.hypot(px - x, py - y)
    vy = v[py, px]
    zx, zy = depth, depth[py, px]
    f = soft_depth_compare(zx, zy, soft_z)
    b = soft_depth_compare(zy, zx, soft_z)
    wa = np.abs(np.sum(wc * d, -1))
    wb = np.abs(np.sum(_direction(vy) * d, -1))
    shorter = np.minimum(len_half(vy), len_half(vx))
    return (
        f * cone(dist, vy) * wb
        + b * cone(dist, vx) * wa
        + cylinder(dist, np.stack([shorter, np.zeros_like(shorter)], -1)) * np.maximum(wa, wb) * 2
    )


def reconstruct_guertin2014(
    color,
    depth,
    motion,
    *,
    k: int,
    samples: int,
    soft_z: float,
    exposure: float,
    seed: int,
    gamma: float,
    kappa: float,
    jitter_tiles: int,
    adaptive_samples: int,
    early_exit: float,
    packed_inputs: bool,
    half_result: bool,
    neighbor: np.ndarray | None = None,
) -> np.ndarray:
    """(H, W, C) float64 blurred color. `neighbor`: NeighborMax (with diagonal_reach) if
    already computed; the options (0 is off) are those of docs/guertin2014.md, and
    packed_inputs reads the inputs as docs/spec.md §19 packs them; half_result rounds the
    result to half floats as the RGBA16F target holds it."""
    options = (jitter_tiles, adaptive_samples, early_exit, packed_inputs)
    start = filter_start(
        color, depth, motion, neighbor, k, samples, exposure, seed, options, diagonal_reach=True
    )
    color, depth, v, x, y, vn, vn_length, moving, n = start
    h, w = depth.shape

    vx = v
    wn = _direction(vn)
    wc = center_direction(vn, vx, gamma)
    # Step 3: the center's weight S / (κ len(V[X])).
    weight = n / (kappa * len_half(vx))
    total = color * weight[..., None]
    j = rand(x, y, seed) - 0.5
    center = np.stack([x, y], -1) + 0.5
    pairs = n // 2
    speed = np.linalg.norm(v, axis=-1)
    for i in range(samples // 2):
        active = i < pairs
        # Step 2: pair i lies at ±t along wn (i even) or wc (i odd), |vN| long.
        t = (i + 0.5 + j) / np.maximum(pairs, 1)
        d = wn if i % 2 == 0 else wc
        step = d * (vn_length * t)[..., None]
        (py1, px1), (py2, px2) = mirrored_taps(center, step, h, w)
        a1 = sample_weight(x, y, px1, py1, depth, v, vx, wc, d, soft_z)
        a2 = sample_weight(x, y, px2, py2, depth, v, vx, wc, d, soft_z)
        # Step 5, the mirror.
        a1, a2 = mirror_pair(
            a1, a2, depth[py1, px1], depth[py2, px2], speed[py1, px1], speed[py2, px2]
        )
        a1, a2 = np.where(active, a1, 0.0), np.where(active, a2, 0.0)
        weight = weight + a1 + a2
        total = total + a1[..., None] * color[py1, px1] + a2[..., None] * color[py2, px2]
    result = np.where(moving[..., None], total / weight[..., None], color)
    return round_to_half(result) if half_result else result
