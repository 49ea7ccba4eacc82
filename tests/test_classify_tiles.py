"""Tile classification (Jimenez 2014; docs/classify_and_steps.md) on the GPU against
bl.twins.classify: TileMax's bounds output, the class map, and the tile lists that the
indirect dispatches read."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

from blurlab import _core
from blurlab.methods import tile_filter
from blurlab.twins import classify as ref
from blurlab.twins import mcguire2012 as m


def structured_motion(rng, width, height, k):
    """Random motion with still blocks and blocks of one motion each (exactly uniform, or
    jittered by up to 0.2 px), so that every class occurs; tie-free like random_frame."""
    frame = random_frame(rng, width, height, k=k)
    motion = frame.motion
    blocks = 3 * k
    for by in range(0, height, blocks):
        for bx in range(0, width, blocks):
            kind = rng.integers(0, 4)
            region = motion[by : by + blocks, bx : bx + blocks]
            if kind == 0:
                region[:] = 0
            elif kind in (1, 2):
                angle = rng.uniform(0, 2 * np.pi)
                length = rng.uniform(2, 1.8 * k)
                region[:] = (length * np.cos(angle), length * np.sin(angle))
                if kind == 2:
                    region += rng.uniform(-0.2, 0.2, region.shape).astype(np.float32)
    return frame


def gpu_classification(ctx, frame, k, uniform_spread, still_threshold=ref.STILL_THRESHOLD):
    """(bounds, neighbor_max, class map, tile lists) computed by the GPU passes."""
    height, width = frame.motion.shape[:2]
    grid = (-(-height // k), -(-width // k))
    motion = ctx.upload(frame.motion)
    classes = ctx.empty(grid)
    values = {"k": k, "exposure": 1.0}
    _, neighbors, _, bounds = tile_filter.tile_passes(
        ctx, motion, tile_filter.TILE_FILTER_PARAMS, values, "compute", with_bounds=True
    )
    lists = _core.TileLists(ctx.native, grid[1], grid[0], k)
    _core.ClassifyTilesPass(ctx.native).run(
        bounds.native, neighbors.native, classes.native, lists, still_threshold, uniform_spread
    )
    return bounds.download(), neighbors.download(), classes.download(), lists


@pytest.mark.parametrize(("k", "size"), [(5, (97, 61)), (20, (160, 90)), (40, (150, 97))])
def test_tile_bounds_match_reference(ctx, rng, k, size):
    frame = structured_motion(rng, *size, k)
    bounds, _, _, _ = gpu_classification(ctx, frame, k, 0.25)
    expected = ref.tile_bounds(m.half_velocity(frame.motion, 1.0, k), k)
    np.testing.assert_allclose(bounds, expected, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize(("k", "size"), [(5, (97, 61)), (8, (128, 72)), (20, (160, 90))])
@pytest.mark.parametrize("uniform_spread", [0.0, 0.25, 1.0])
def test_classification_matches_reference(ctx, rng, k, size, uniform_spread):
    frame = structured_motion(rng, *size, k)
    bounds, neighbors, classes, lists = gpu_classification(ctx, frame, k, uniform_spread)
    v = m.half_velocity(frame.motion, 1.0, k)
    expected = ref.classify_tiles(
        ref.tile_bounds(v, k), m.neighbor_max(m.tile_max(v, k)), uniform_spread=uniform_spread
    )
    np.testing.assert_array_equal(classes, expected)
    counts = np.bincount(expected.ravel(), minlength=3)
    assert list(lists.counts()) == list(counts)
    for c in range(3):
        listed = sorted(tuple(t) for t in lists.tiles(c))
        ty, tx = np.nonzero(expected == c)
        assert listed == sorted(zip(tx.tolist(), ty.tolist(), strict=True))
    if uniform_spread >= 0.25:  # the structured motion has exactly uniform blocks
        assert counts.min() > 0, counts


def test_still_threshold_is_the_filters_early_exit(ctx, rng):
    frame = structured_motion(rng, 120, 80, 10)
    frame.motion *= 0.0
    frame.motion[:40, :40] = (1.0, 0.5)  # |V| = 0.56 px > 0.51
    _, _, classes, lists = gpu_classification(ctx, frame, 10, 0.25)
    assert classes[:5, :5].max() > 0 and classes[6:].max() == 0
    _, _, all_still, _ = gpu_classification(ctx, frame, 10, 0.25, still_threshold=1.0)
    assert all_still.max() == 0


def test_too_many_tiles_for_the_device_names_k(ctx):
    # 65535^2 tiles exceed every device's work-group limit (2^31 - 1 on NVIDIA, 65535 on Mesa).
    with pytest.raises(ValueError, match="use a larger k"):
        _core.TileLists(ctx.native, 65535, 65535, 1)
