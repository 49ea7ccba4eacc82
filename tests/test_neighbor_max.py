"""NeighborMax (docs/spec.md §3.3) on the GPU against bl.twins.mcguire2012.neighbor_max."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.twins import mcguire2012 as ref


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "size"), [(1, (19, 13)), (5, (64, 40)), (20, (160, 90)), (64, (200, 70))]
)
def test_neighbor_max_equals_reference(ctx, rng, backend, k, size):
    frame = random_frame(rng, *size, k=k)
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", backend=backend, k=k)
    expected = ref.neighbor_max(result.buffers["tile_max"].astype(np.float64))
    np.testing.assert_array_equal(result.buffers["neighbor_max"], expected.astype(np.float32))


def test_neighbor_max_spreads_one_tile_to_its_ring():
    tiles = np.zeros((5, 6, 2))
    tiles[2, 3] = (3.0, 4.0)
    spread = ref.neighbor_max(tiles)
    ring = np.zeros((5, 6), bool)
    ring[1:4, 2:5] = True
    assert (np.linalg.norm(spread, axis=-1) == 5.0).sum() == 9
    assert (np.linalg.norm(spread[ring], axis=-1) == 5.0).all()
