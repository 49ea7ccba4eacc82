"""Textures: exact round trips, orientation, validation, and no leaked GL objects."""

from __future__ import annotations

import numpy as np
import pytest

DTYPES = ["uint8", "float16", "float32"]


def random_image(rng, shape, dtype):
    if dtype == "uint8":
        return rng.integers(0, 256, size=shape, dtype=np.uint8)
    bits = np.uint16 if dtype == "float16" else np.uint32
    # Random bit patterns cover denormals and extreme exponents; NaN payloads are left out
    # because they are not values (their bits are only promised by the transfer, checked below).
    image = rng.integers(0, np.iinfo(bits).max, size=shape, dtype=bits).view(dtype)
    return np.where(np.isnan(image), np.asarray(0.5, dtype), image)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("channels", [None, 1, 2, 3, 4])
def test_round_trip_is_bit_exact(ctx, rng, dtype, channels):
    shape = (37, 53) if channels is None else (37, 53, channels)  # odd sizes: no row padding
    image = random_image(rng, shape, dtype)
    texture = ctx.upload(image)
    back = texture.download()
    assert back.shape == image.shape and back.dtype == image.dtype
    assert back.tobytes() == image.tobytes()


@pytest.mark.parametrize("dtype", ["float16", "float32"])
def test_special_float_values_survive(ctx, dtype):
    values = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1e-40, -1e-42, 6e-8], dtype=dtype)
    image = np.tile(values, (3, 1))
    back = ctx.upload(image).download()
    assert back.tobytes() == image.tobytes()


def test_row_zero_is_the_top(ctx):
    image = np.repeat(np.arange(6, dtype=np.float32)[:, None], 4, axis=1)  # value = row index
    texture = ctx.upload(image)
    out = ctx.empty((6, 4, 4))
    probe = ctx.program("util/test_pattern.comp")
    probe.run((4, 6), images=[(out, "write")], uniforms={"seed": 0})
    # The pattern's v channel grows with the row: texel row 0 is image row 0 on the GPU too.
    v = out.download()[:, 0, 1]
    assert np.all(np.diff(v) > 0) and v[0] < 0.5
    np.testing.assert_array_equal(texture.download()[:, 0], np.arange(6))


def test_non_contiguous_input_is_copied(ctx, rng):
    image = rng.random((20, 30, 4), dtype=np.float32)
    view = image[:, ::2, :]
    assert not view.flags.c_contiguous
    np.testing.assert_array_equal(ctx.upload(view).download(), view)


def test_upload_replaces_contents(ctx, rng):
    texture = ctx.empty((8, 9, 2), "float16")
    assert not texture.download().any()
    image = rng.random((8, 9, 2)).astype(np.float16)
    texture.upload(image)
    np.testing.assert_array_equal(texture.download(), image)
    with pytest.raises(ValueError, match="shapes and dtypes must match"):
        texture.upload(image[:4])


@pytest.mark.parametrize(
    ("array", "error", "message"),
    [
        (np.zeros((4, 4, 5), np.float32), ValueError, r"C in 1\.\.4"),
        (np.zeros((4,), np.float32), ValueError, r"\(H, W\)"),
        (np.zeros((2, 4, 4, 1), np.float32), ValueError, r"\(H, W\)"),
        (np.zeros((0, 4, 4), np.float32), ValueError, "empty"),
        (np.zeros((4, 4), np.float64), TypeError, "uint8, float16, float32"),
        (np.zeros((4, 4), np.int32), TypeError, "uint8, float16, float32"),
        (np.zeros((4, 4), bool), TypeError, "uint8, float16, float32"),
        ([[0.0, 1.0]], TypeError, "numpy.ndarray"),
    ],
)
def test_bad_arrays_are_rejected(ctx, array, error, message):
    with pytest.raises(error, match=message):
        ctx.upload(array)


def test_size_beyond_device_limit_is_rejected(ctx):
    limit = ctx.max_texture_size
    with pytest.raises(ValueError, match="GL_MAX_TEXTURE_SIZE"):
        ctx.empty((1, limit + 1))


def test_empty_rejects_bad_shape_and_dtype(ctx):
    with pytest.raises(ValueError, match="C in 1..4"):
        ctx.empty((4, 4, 0))
    with pytest.raises(TypeError, match="float16"):
        ctx.empty((4, 4), "int16")


def test_freeing_textures_returns_live_count(ctx, rng):
    before = ctx.live_objects().get("texture", 0)
    image = rng.random((16, 16, 4), dtype=np.float32)
    textures = [ctx.upload(image) for _ in range(500)]
    assert ctx.live_objects()["texture"] == before + 500
    del textures
    assert ctx.live_objects()["texture"] == before


@pytest.mark.parametrize("dtype", DTYPES)
def test_async_download_matches_sync(ctx, rng, dtype):
    image = random_image(rng, (33, 47, 4), dtype)
    texture = ctx.upload(image)
    pending = [texture.download_async() for _ in range(3)]  # several in flight at once
    for p in pending:
        assert p.result().tobytes() == image.tobytes()


def test_async_download_recycles_its_buffer_and_reads_again(ctx, rng):
    image = rng.random((10, 12, 4), dtype=np.float32)
    texture = ctx.upload(image)
    pending = texture.download_async()
    first, second = pending.result(), pending.result()  # each a new array of the same bytes
    np.testing.assert_array_equal(first, image)
    np.testing.assert_array_equal(second, image)
    first[...] = 0  # the caller's own copy
    np.testing.assert_array_equal(pending.result(), image)
    del pending
    buffers = ctx.live_objects()["buffer"]
    np.testing.assert_array_equal(texture.download_async().result(), image)  # the pooled one
    assert ctx.live_objects()["buffer"] == buffers
