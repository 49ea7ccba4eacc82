"""The scatter dilation of tiles (docs/spec.md §17.6, "Steps 1–2 by scatter"), which
gather_coverage runs: the tile flatten offers each tile's reach to the tiles it meets by atomic
max on 32-bit keys and a small pass resolves them. It must give the same bits as the gather
dilation in both thread modes, agree with the twin's picks (ties to the first source, lengths
past PICK_KEY_MAX tied), and hand grids too large for its 12-bit index to the gather dilation.
Also the uint32 textures the keys live in. The methods' own use of it is tested in their folders
(test_<name>_scatter.py, test_<name>_dilation.py)."""

from __future__ import annotations

import numpy as np
import pytest
from tied_tiles import CASES, tied_frame

import blurlab as bl
from blurlab.methods import eevee
from blurlab.twins import coverage as coverage_twin
from blurlab.twins import eevee as twin

STEPS = coverage_twin.TILE_LENGTH_STEPS


def stepped_tiles(ctx, frame, tile_size, max_blur, group_per_tile, dilation):
    """(tiles, dilated, pass names) with lengths in 1/16 px steps, the dilation as named."""
    timings: dict = {}
    with eevee.DILATION_LAYOUT.use(dilation):
        _, tiles, dilated, _ = eevee.dilated_tiles(
            ctx,
            frame,
            timings,
            eevee.PARAMS,
            {"exposure": 1.0},
            frame.color.shape[:2],
            tile_size,
            max_blur,
            group_per_tile,
            length_steps=STEPS,
        )
    arrays = tiles.download(), dilated.download(), list(timings)
    ctx.recycle(tiles, dilated)
    return arrays


@pytest.mark.parametrize("group_per_tile", [False, True])
@pytest.mark.parametrize(("size", "tile_size", "max_blur", "scale"), CASES)
def test_scatter_gives_the_gather_dilations_bits(
    ctx, rng, size, tile_size, max_blur, scale, group_per_tile
):
    frame = tied_frame(rng, *size, scale)
    gathered = stepped_tiles(ctx, frame, tile_size, max_blur, group_per_tile, "gather")
    scattered = stepped_tiles(ctx, frame, tile_size, max_blur, group_per_tile, "scatter")
    assert "tile_dilate" in gathered[2] and "tile_dilate" not in scattered[2]
    assert scattered[2] == ["reach_keys_clear", "tile_flatten", "tile_resolve"]
    assert gathered[0].tobytes() == scattered[0].tobytes()
    assert gathered[1].tobytes() == scattered[1].tobytes()
    # and the twin's picks, ties to the first source in row order
    expected = twin.tile_dilate(scattered[0].astype(np.float64), tile_size, max_blur, STEPS)
    assert scattered[1].tobytes() == expected.astype(np.float32).tobytes()
    assert len(np.unique(scattered[1].reshape(-1, 4), axis=0)) > 2  # picks really vary


@pytest.mark.parametrize("group_per_tile", [False, True])
def test_lengths_past_the_largest_key_tie_and_the_first_source_wins(ctx, group_per_tile):
    # Two tiles moving far beyond PICK_KEY_MAX steps (16384 px), the later one longer: both
    # reach tile (0, 1) and its key ties them, so the first in row order wins there, in the
    # twin as on the GPU; a plain float comparison would have taken the longer.
    height, width = 8, 24  # 8 px tiles: one row of three
    halves = np.zeros((height, width, 2), np.float32)
    halves[:, 0:8] = (1e5, 0.0)  # tile 0 moves right
    halves[:, 16:24] = (-3e5, 0.0)  # tile 2 moves left, longer
    frame = bl.Frame(
        np.zeros((height, width, 4), np.float32),
        np.ones((height, width), np.float32),
        2 * halves,
        motion_prev=-halves,  # prev = -next: the reach of both sides runs along +next
        motion_next=halves,
    )
    assert twin.pick_key(np.float32(3e5), STEPS) == twin.pick_key(np.float32(1e5), STEPS)
    assert twin.pick_key(np.float32(3e5), STEPS) == twin.PICK_KEY_MAX
    for dilation in ("gather", "scatter"):
        tiles, dilated, _ = stepped_tiles(ctx, frame, 8, 16.0, group_per_tile, dilation)
        assert dilated[0, 1, 2:].tolist() == [1e5, 0.0]  # tile 0's, not tile 2's
        expected = twin.tile_dilate(tiles.astype(np.float64), 8, 16.0, STEPS)
        assert dilated.tobytes() == expected.astype(np.float32).tobytes()


def test_grids_beyond_the_key_index_take_the_gather_dilation(ctx, rng):
    # A 4097-tile frame would be slow on llvmpipe: lower the limit under the test frame's
    # 9 x 5 = 45 tiles instead.
    frame = tied_frame(rng, 72, 40, 2.0)
    _, _, names = stepped_tiles(ctx, frame, 8, 16.0, False, "scatter")
    assert "tile_resolve" in names
    limit = eevee.SCATTER_MAX_TILES
    try:
        eevee.SCATTER_MAX_TILES = 44  # 9 x 5 = 45 tiles: one too many
        _, _, names = stepped_tiles(ctx, frame, 8, 16.0, False, "scatter")
    finally:
        eevee.SCATTER_MAX_TILES = limit
    assert "tile_dilate" in names and "tile_resolve" not in names


def test_uint32_textures_round_trip_and_clear(ctx):
    values = np.array([[0, 1, 2**31], [2**32 - 1, 12345, 7]], np.uint32)
    texture = ctx.upload(values)
    back = texture.download()
    assert back.dtype == np.uint32 and back.tobytes() == values.tobytes()
    texture.clear()
    assert not texture.download().any()
    pooled = ctx.pooled((3, 5), "uint32")
    assert pooled.dtype == np.uint32 and pooled.shape == (3, 5)
    assert ctx.gl_errors() == []


def test_a_texture_of_the_wrong_kind_is_refused(ctx):
    # GL reads a float texture through a usampler2D (or the reverse) as undefined values, not
    # an error: the pass says which sampler or image wants which kind instead.
    resolve = ctx.shader_pass("passes/eevee_tile_resolve.glsl")
    tiles, dilated = ctx.empty((3, 4, 4)), ctx.empty((3, 4, 4))
    with pytest.raises(ValueError, match="sampler 'reach_keys' reads integers.*uint32"):
        resolve.run({"tiles": tiles, "reach_keys": ctx.empty((6, 4))}, {"dilated": dilated})
    with pytest.raises(ValueError, match="sampler 'tiles' reads floats"):
        keys = ctx.empty((6, 4), "uint32")
        resolve.run(
            {"tiles": ctx.empty((3, 4, 4), "uint32"), "reach_keys": keys}, {"dilated": dilated}
        )
    clear = ctx.shader_pass("passes/reach_keys_clear.glsl")
    with pytest.raises(ValueError, match="image 'reach_keys' reads integers"):
        clear.run({}, {"reach_keys": ctx.empty((6, 4))})
    resolve.run({"tiles": tiles, "reach_keys": ctx.empty((6, 4), "uint32")}, {"dilated": dilated})
    assert not dilated.download().any()  # no keys: nothing kept
    assert ctx.gl_errors() == []
