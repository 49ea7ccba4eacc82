"""The options of the reconstruction filters (docs/guertin2014.md "Options"): jittered tile
lookup, adaptive sample count, early exit threshold — each on reconstruct_mcguire2012 and
reconstruct_guertin2014, on the GPU against the NumPy references, with the 2012 invariants."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_matches_twin, random_frame

import blurlab as bl
from blurlab.twins import mcguire2012

# Every filter that offers the options, from the registry.
FILTERS = [name for name in bl.methods() if "jitter_tiles" in bl.method(name).params]
OPTIONS = [
    {"jitter_tiles": 1},
    {"adaptive_samples": 1},
    {"early_exit": 6.0},
    {"jitter_tiles": 1, "adaptive_samples": 1, "early_exit": 2.0},
]


def moved(frame, scale):
    """A new frame (its own textures) with the motion scaled by `scale`."""
    motion = (frame.motion * np.asarray(scale, np.float32)).astype(np.float32)
    return bl.Frame(color=frame.color.copy(), depth=frame.depth.copy(), motion=motion)


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("options", OPTIONS, ids=lambda o: "+".join(o))
@pytest.mark.parametrize("method", list(FILTERS))
def test_options_match_reference(ctx, rng, method, options, backend):
    frame = random_frame(rng, 123, 71, k=12)
    result = bl.blur(ctx, frame, method, backend=backend, k=12, soft_z=0.5, seed=5, **options)
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("options", OPTIONS, ids=lambda o: "+".join(o))
@pytest.mark.parametrize("method", list(FILTERS))
def test_options_keep_the_invariants(ctx, rng, method, options):
    frame = random_frame(rng, 96, 64, k=10)
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25
    out = bl.blur(ctx, frame, method, k=10, **options).color
    assert np.isfinite(out).all()
    lo, hi = frame.color.min(axis=(0, 1)), frame.color.max(axis=(0, 1))
    assert (out >= lo - 1e-6).all() and (out <= hi + 1e-6).all()
    assert bl.blur(ctx, frame, method, k=10, **options).color.tobytes() == out.tobytes()
    still = bl.blur(ctx, moved(frame, 0.0), method, k=10, **options).color
    assert still.tobytes() == frame.color.tobytes()


@pytest.mark.parametrize("method", list(FILTERS))
def test_early_exit_keeps_pixels_whose_neighborhood_moves_less(ctx, rng, method):
    frame = random_frame(rng, 80, 48, k=8)  # motions up to 1.9 k = 15.2 px
    off = bl.blur(ctx, frame, method, k=8).color
    assert bl.blur(ctx, frame, method, k=8, early_exit=40.0).color.tobytes() == (
        frame.color.tobytes()
    )
    scale = np.ones((48, 80, 1), np.float32)
    scale[:, :40] = 0.1  # the left half moves < 1.6 px; the right half as before
    frame = moved(frame, scale)
    out = bl.blur(ctx, frame, method, k=8, early_exit=2.0).color
    assert out[:, :24].tobytes() == frame.color[:, :24].tobytes()  # 2 tiles from the right half
    assert not np.array_equal(out[:, :24], bl.blur(ctx, frame, method, k=8).color[:, :24])
    assert not np.array_equal(off, frame.color)


@pytest.mark.parametrize("method", list(FILTERS))
def test_adaptive_samples_change_only_short_neighborhoods(ctx, rng, method):
    frame = random_frame(rng, 80, 48, k=40)
    frame = moved(frame, 40.0 / np.linalg.norm(frame.motion, axis=-1, keepdims=True))  # |V| = 20
    params = {"k": 40, "samples": 15}
    full = bl.blur(ctx, frame, method, **params).color
    assert bl.blur(ctx, frame, method, adaptive_samples=1, **params).color.tobytes() == (
        full.tobytes()
    )  # |vN| = 20 >= S: all S samples
    frame = moved(frame, 0.2)  # |vN| = 4: 4 samples instead of 15
    full = bl.blur(ctx, frame, method, **params).color
    fewer = bl.blur(ctx, frame, method, adaptive_samples=1, **params).color
    assert not np.array_equal(full, fewer)


@pytest.mark.parametrize("method", list(FILTERS))
def test_jittered_lookup_is_invisible_under_uniform_motion(ctx, rng, method):
    frame = random_frame(rng, 96, 64, k=16)
    frame = moved(frame, 0.0)
    frame.motion[:] = (9.0, -5.0)  # every tile's NeighborMax is the same vector
    plain = bl.blur(ctx, frame, method, k=16).color
    jittered = bl.blur(ctx, frame, method, k=16, jitter_tiles=1).color
    assert jittered.tobytes() == plain.tobytes()
    frame = random_frame(rng, 96, 64, k=16)
    plain = bl.blur(ctx, frame, method, k=16).color
    assert not np.array_equal(bl.blur(ctx, frame, method, k=16, jitter_tiles=1).color, plain)


def test_jittered_lookup_moves_a_quarter_tile_never_diagonally():
    k = 16
    y, x = np.mgrid[0:200, 0:300]
    ty, tx = mcguire2012.lookup_tile(x, y, k, seed=9, jitter=True, grid=(13, 19))
    dy, dx = ty - y // k, tx - x // k
    assert (np.abs(dx) <= 1).all() and (np.abs(dy) <= 1).all()
    assert not ((dx != 0) & (dy != 0)).any()
    inner = (x % k >= k // 4) & (x % k < k - k // 4) & (y % k >= k // 4) & (y % k < k - k // 4)
    assert (dx[inner] == 0).all() and (dy[inner] == 0).all()  # a quarter tile from the border
    assert 0.2 < ((dx != 0) | (dy != 0)).mean() < 0.6  # near borders: often another tile


@pytest.mark.parametrize(
    ("params", "error", "message"),
    [
        ({"jitter_tiles": 2}, ValueError, "jitter_tiles = 2 is outside 0..1"),
        ({"adaptive_samples": -1}, ValueError, "adaptive_samples"),
        ({"jitter_tiles": True}, TypeError, "jitter_tiles must be an integer"),
        ({"early_exit": -1.0}, ValueError, r"early_exit = -1.0 is outside \[0, "),
        ({"early_exit": float("nan")}, ValueError, "early_exit must be finite"),
    ],
)
@pytest.mark.parametrize("method", list(FILTERS))
def test_bad_options_name_the_range(ctx, rng, method, params, error, message):
    with pytest.raises(error, match=message):
        bl.blur(ctx, random_frame(rng, 16, 16), method, **params)
