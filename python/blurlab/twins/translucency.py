"""Translucent surfaces, docs/spec.md §20, in NumPy float64: the per-pixel resolve of fragment
lists (GPU twin: shaders/passes/translucent_resolve.comp) and the compositing step of the four
ways to blur translucency (GPU twin: shaders/passes/translucent_resolve.comp)."""

from __future__ import annotations

import numpy as np

ADDITIVE = 3  # the alpha mode stored with a fragment (src/passes/gbuffer.h AlphaMode)
RESOLVED = ("composite", "translucent", "translucent_motion")  # what resolve returns


def resolve(opaque_color, counts, surface, motion) -> dict[str, np.ndarray]:
    """Sorts each pixel's fragments back to front and composites them (§20).

    opaque_color (H, W, 4); counts (H, W) fragments listed per pixel (those past the capacity
    included, then ignored); surface and motion (K, H, W, 4): premultiplied colour and coverage,
    and depth, motion x, motion y, alpha mode, fragment k of each pixel in [k].
    Returns "composite" (H, W, 4), "translucent" (Σ, a) and "translucent_motion" (dominant
    fragment's motion x, y, depth, and the count)."""
    opaque_color = np.asarray(opaque_color, np.float64)
    surface = np.asarray(surface, np.float64)
    motion = np.asarray(motion, np.float64)
    capacity = surface.shape[0]
    counts = np.asarray(counts)
    listed = np.arange(capacity)[:, None, None] < np.minimum(counts, capacity)[None]
    # Back to front: greater depth first, then the other values in the shader's order; fragments
    # not listed go last. np.lexsort's last key is the primary one.
    keys = [
        -motion[..., 2],
        -motion[..., 1],
        -motion[..., 3],
        -surface[..., 2],
        -surface[..., 1],
        -surface[..., 0],
        -surface[..., 3],
        -motion[..., 0],
        ~listed,
    ]
    order = np.lexsort([np.where(listed, k, 0.0) if k.dtype != bool else k for k in keys], axis=0)
    surface = np.take_along_axis(surface, order[..., None], axis=0)
    motion = np.take_along_axis(motion, order[..., None], axis=0)
    listed = np.take_along_axis(listed, order, axis=0)
    color = opaque_color.copy()
    total = np.zeros(opaque_color.shape[:2] + (3,))
    coverage = np.zeros(opaque_color.shape[:2] + (1,))
    for k in range(capacity):  # back to front
        on = listed[k][..., None]
        premultiplied, alpha = surface[k, ..., :3], surface[k, ..., 3:]
        color[..., :3] = np.where(on, premultiplied + (1 - alpha) * color[..., :3], color[..., :3])
        total = np.where(on, premultiplied + (1 - alpha) * total, total)
        coverage = np.where(on, alpha + (1 - alpha) * coverage, coverage)
    dominant = np.zeros(opaque_color.shape[:2] + (3,))
    dominant[..., 2] = np.inf
    best = np.zeros(opaque_color.shape[:2])
    transmittance = np.ones(opaque_color.shape[:2])
    for k in reversed(range(capacity)):  # front to back
        on = listed[k]
        weight = strength(surface[k], motion[k]) * transmittance
        better = on & (weight > best)
        best = np.where(better, weight, best)
        dominant = np.where(better[..., None], motion[k][..., [1, 2, 0]], dominant)
        transmittance = np.where(on, transmittance * (1 - surface[k, ..., 3]), transmittance)
    return {
        "composite": color,
        "translucent": np.concatenate([total, coverage], axis=-1),
        "translucent_motion": np.concatenate([dominant, counts[..., None]], axis=-1),
    }


def strength(surface, motion) -> np.ndarray:
    """How much of the image a fragment makes: its coverage (blend), or its brightest
    premultiplied channel, at most 1 (additive, which covers nothing)."""
    additive = motion[..., 3] == ADDITIVE
    brightest = np.minimum(1.0, surface[..., :3].max(axis=-1))
    return np.where(additive, brightest, surface[..., 3])


def chosen_motion(translucent, translucent_motion, translucent_depth, motion, depth, coverage):
    """composite_motion (§20.4): (motion, depth) of the translucent layer's dominant fragment
    where its coverage a ≥ `coverage` and it has one, the opaque layer's elsewhere."""
    own = (np.asarray(translucent)[..., 3] >= coverage) & np.isfinite(translucent_depth)
    return (
        np.where(own[..., None], translucent_motion, motion),
        np.where(own, translucent_depth, depth),
    )


def over(layer, opaque) -> np.ndarray:
    """The layer (Σ, a) over the opaque colour, premultiplied: Σ + (1 − a)·opaque (§20.4)."""
    layer, opaque = np.asarray(layer, np.float64), np.asarray(opaque, np.float64)
    out = opaque.copy()
    out[..., :3] = layer[..., :3] + (1 - layer[..., 3:]) * opaque[..., :3]
    return out
