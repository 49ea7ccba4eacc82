"""Image files: EXR keeps floats, PNG is 8-bit sRGB, failures leave no partial file."""

from __future__ import annotations

import os

import numpy as np
import pytest

import blurlab as bl


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_exr_keeps_float32_exactly(tmp_path, rng, channels):
    image = (rng.standard_normal((9, 13, channels)) * 100).astype(np.float32)
    path = bl.io.write(tmp_path / "a.exr", image)
    back = bl.io.read(path)
    assert back.dtype == np.float32 and back.shape == image.shape
    np.testing.assert_array_equal(back, image)


def test_exr_keeps_half_values(tmp_path, rng):
    image = rng.random((5, 6, 2)).astype(np.float16)
    back = bl.io.read(bl.io.write(tmp_path / "h.exr", image))
    np.testing.assert_array_equal(back, image.astype(np.float32))


def test_png_encodes_linear_float_as_srgb(tmp_path):
    linear = np.linspace(0, 1, 256, dtype=np.float32).reshape(1, 256, 1).repeat(3, axis=2)
    back = bl.io.read(bl.io.write(tmp_path / "ramp.png", linear))
    assert back.dtype == np.uint8
    expected = np.round(bl.io.linear_to_srgb(linear) * 255).astype(np.uint8)
    np.testing.assert_array_equal(back, expected)
    assert back[0, 128, 0] > 128  # sRGB brightens mid grey: 0.5 linear is about 188


def test_png_uint8_round_trip(tmp_path, rng):
    image = rng.integers(0, 256, (7, 11, 4), dtype=np.uint8)
    np.testing.assert_array_equal(bl.io.read(bl.io.write(tmp_path / "b.png", image)), image)


def test_srgb_round_trip():
    x = np.linspace(0, 1, 101)
    np.testing.assert_allclose(bl.io.srgb_to_linear(bl.io.linear_to_srgb(x)), x, atol=1e-12)


def test_bad_extension_and_arrays_are_rejected(tmp_path):
    with pytest.raises(ValueError, match=r"\.exr, \.png"):
        bl.io.write(tmp_path / "a.bmp", np.zeros((2, 2), np.float32))
    with pytest.raises(ValueError, match="NaN"):
        bl.io.write(tmp_path / "a.png", np.full((2, 2), np.nan, np.float32))
    with pytest.raises(TypeError, match="dtype"):
        bl.io.write(tmp_path / "a.exr", np.zeros((2, 2), np.int64))
    with pytest.raises(ValueError, match="non-empty"):
        bl.io.write(tmp_path / "a.exr", np.zeros((0, 2), np.float32))
    assert list(tmp_path.iterdir()) == []


def test_missing_folder_raises_and_writes_nothing(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        bl.io.write(tmp_path / "no" / "such" / "a.exr", np.zeros((2, 2), np.float32))
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_no_partial_file_and_keeps_the_old_one(tmp_path, monkeypatch):
    target = tmp_path / "keep.exr"
    old = np.ones((3, 3), np.float32)
    bl.io.write(target, old)

    def fail(*args, **kwargs):
        raise OSError("disk full (simulated)")

    monkeypatch.setattr(os, "replace", fail)
    with pytest.raises(OSError, match="simulated"):
        bl.io.write(target, np.zeros((3, 3), np.float32))
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.exr"]
    np.testing.assert_array_equal(bl.io.read(target)[..., 0], old)


def test_corrupt_and_missing_files_raise_clearly(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        bl.io.read(tmp_path / "absent.exr")
    good = bl.io.write(tmp_path / "good.exr", np.ones((64, 64, 4), np.float32))
    truncated = tmp_path / "truncated.exr"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    with pytest.raises(OSError, match="truncated|corrupt|cannot read"):
        bl.io.read(truncated)
    garbage = tmp_path / "garbage.png"
    garbage.write_bytes(b"not a png at all")
    with pytest.raises(OSError):
        bl.io.read(garbage)


def test_written_files_get_the_processs_normal_permissions(tmp_path):
    """Atomic writes go through a 0600 temporary file; the result must still be 0666 less the
    umask, so a web server or a colleague can read it."""
    previous = os.umask(0o022)
    try:
        png = bl.io.write(tmp_path / "a.png", np.zeros((4, 4, 3), np.float32))
        text = bl.io.write_text(tmp_path / "a.html", "<p>hi</p>")
    finally:
        os.umask(previous)
    assert png.stat().st_mode & 0o777 == 0o644
    assert text.stat().st_mode & 0o777 == 0o644 and text.read_text() == "<p>hi</p>"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.html", "a.png"]  # no temporaries


def test_srgb8_by_table_gives_the_formulas_bytes_at_every_step():
    # srgb8 looks codes up in a table (10-40x faster than the formulas on the study's pictures); the
    # bytes must be those of the float64 transfer function, right at each code's first value
    # and one float below it, for float32 and float64 input alike.
    formula = lambda x: np.round(bl.io.linear_to_srgb(x) * 255.0).astype(np.uint8)  # noqa: E731
    for dtype in (np.float32, np.float64):
        edges = []
        for code in range(1, 256):
            low, high = dtype(0.0), dtype(1.0)  # bisect for the first value of `code`
            for _ in range(80):
                middle = dtype((low + high) / 2)
                if middle in (low, high):
                    break
                if formula(np.array([middle]))[0] >= code:
                    high = middle
                else:
                    low = middle
            edges += [low, high, np.nextafter(high, dtype(2.0))]
        values = np.array(edges + [0.0, 1.0, -0.0, 1e-30, 0.5, -3.0, 7.0], dtype)
        values = np.concatenate([values, np.random.default_rng(5).random(20000).astype(dtype)])
        assert np.array_equal(bl.io.srgb8(values), formula(values)), dtype
    specials = np.array([np.nan, np.inf, -np.inf], np.float32)
    assert bl.io.srgb8(specials).tolist() == [0, 255, 0]
    assert bl.io.srgb8(specials.astype(np.float64)).tolist() == [0, 255, 0]
    assert bl.io.srgb8(np.zeros((2, 3, 4), np.float32)).shape == (2, 3, 4)
