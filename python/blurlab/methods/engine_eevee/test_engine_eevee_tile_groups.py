"""engine_eevee's tile flatten and dilation (docs/spec.md §17.2 steps 1-2, shared with another
method: blurlab.methods.eevee) run a work group per tile on a GPU and one thread per tile on
llvmpipe (eevee.tile_groups): both modes give the same bits, ties (equal lengths) go to the
first candidate in row-major order as the NumPy twin says, and a tile whose first pixel moves
by a signed zero keeps that zero's sign."""

from __future__ import annotations

import numpy as np
import pytest
from tied_tiles import CASES, tied_frame

from blurlab.methods import eevee
from blurlab.twins import eevee as twin


def tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile):
    """(tiles, dilated) as the method's passes make them in the given mode, exposure 1."""
    values = {"exposure": 1.0}
    size = frame.color.shape[:2]
    _, tiles, dilated, _ = eevee.dilated_tiles(
        ctx, frame, {}, eevee.PARAMS, values, size, tile_size, max_blur, group_per_tile
    )
    arrays = tiles.download(), dilated.download()
    ctx.recycle(tiles, dilated)
    return arrays


@pytest.mark.parametrize(("size", "tile_size", "max_blur", "scale"), CASES)
def test_both_modes_give_the_same_bits(ctx, rng, size, tile_size, max_blur, scale):
    frame = tied_frame(rng, *size, scale)
    threads = tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile=False)
    groups = tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile=True)
    for one, other in zip(threads, groups, strict=True):
        assert one.tobytes() == other.tobytes()


@pytest.mark.parametrize("variant", list(eevee.TILE_PICK_VARIANTS))
@pytest.mark.parametrize(("size", "tile_size", "max_blur", "scale"), CASES)
def test_every_group_layout_gives_the_same_bits(
    ctx, rng, variant, size, tile_size, max_blur, scale
):
    # Layouts with fewer invocations than a tile's candidates and with more (4 px tiles: 16
    # pixels for up to 256 invocations); the *_subgroup ones reduce in shared memory where the
    # driver lacks subgroup operations (llvmpipe), so on a GPU `blurlab bench layouts`
    # --variants checks their bits again.
    frame = tied_frame(rng, *size, scale)
    threads = tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile=False)
    with eevee.TILE_PICK_LAYOUT.use(variant):
        groups = tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile=True)
    for one, other in zip(threads, groups, strict=True):
        assert one.tobytes() == other.tobytes()


def test_an_unknown_layout_is_refused():
    with pytest.raises(ValueError, match="rows_128_subgroup"), eevee.TILE_PICK_LAYOUT.use("rows_7"):
        pass


@pytest.mark.parametrize("group_per_tile", [False, True])
@pytest.mark.parametrize(("size", "tile_size", "max_blur", "scale"), CASES)
def test_ties_go_to_the_first_candidate_as_the_twin_says(
    ctx, rng, size, tile_size, max_blur, scale, group_per_tile
):
    frame = tied_frame(rng, *size, scale)
    tiles, dilated = tile_buffers(ctx, frame, tile_size, max_blur, group_per_tile)
    expected = twin.tile_flatten(frame.motion_prev, frame.motion_next, tile_size)
    assert tiles.tobytes() == expected.astype(np.float32).tobytes()
    # The frame really has ties: most tiles' longest is 10 · scale, reached in several directions.
    longest = np.linalg.norm(tiles[..., :2], axis=-1) == 10 * scale
    assert longest.mean() > 0.9 and len(np.unique(tiles[longest][:, :2], axis=0)) > 1
    expected = twin.tile_dilate(tiles.astype(np.float64), tile_size, max_blur)
    assert dilated.tobytes() == expected.astype(np.float32).tobytes()


@pytest.mark.parametrize("group_per_tile", [False, True])
def test_a_first_pixel_moving_by_minus_zero_keeps_its_sign(ctx, rng, group_per_tile):
    frame = tied_frame(rng, 40, 24, 1.0)
    for half in (frame.motion_prev, frame.motion_next):
        half[:] = 0.0
        half[0:8:8, 0:40:8] = (-0.0, 0.0)  # each 8 px tile's first pixel, top row of tiles
    tiles, dilated = tile_buffers(ctx, frame, 8, 16.0, group_per_tile)
    for grid in (tiles, dilated):
        assert np.signbit(grid[0, :, 0::2]).all()  # x of both sides: -0, from the first pixel
        assert not np.signbit(grid[1:]).any() and not grid.any()
