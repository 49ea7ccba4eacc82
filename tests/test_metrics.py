"""Metrics against known values, and the GPU's error reduction against NumPy."""

from __future__ import annotations

import math

import numpy as np
import pytest

from blurlab import metrics


def test_identical_images(rng):
    image = rng.random((40, 60, 4))
    assert metrics.psnr(image, image) == math.inf
    assert metrics.ssim(image, image) == pytest.approx(1.0)
    assert metrics.flip(image, image) == pytest.approx(0.0, abs=1e-6)
    assert not metrics.error_map(image, image).any()


def test_known_noise_gives_the_expected_psnr(rng):
    image = np.full((200, 200, 3), 0.5)
    noisy = image + rng.choice([-0.1, 0.1], size=image.shape)  # MSE exactly 0.01
    assert metrics.psnr(image, noisy) == pytest.approx(20.0, abs=1e-9)
    assert metrics.ssim(image, noisy) < 0.5
    assert 0 < metrics.flip(image, noisy) < 1


def test_clipping_to_unit_range():
    assert metrics.mse(np.full((4, 4, 3), 2.0), np.ones((4, 4, 3))) == 0.0


def test_ssim_falls_with_blur(rng):
    image = rng.random((64, 64, 3))
    soft = metrics.ldr.gaussian_blur(image[..., 0], 1.0, 3)[..., None].repeat(3, axis=2)
    assert metrics.ssim(image, soft) < 0.9


def test_flicker_on_still_pixels(rng):
    frames = np.zeros((3, 8, 8, 3))
    frames[1, :4] = 0.3
    still = np.zeros((8, 8), bool)
    still[:4] = True
    assert metrics.flicker(frames, still) == pytest.approx(0.3)
    with pytest.raises(ValueError, match="mask"):
        metrics.flicker(frames, np.zeros((8, 8), bool))


def test_shapes_must_match(rng):
    with pytest.raises(ValueError, match="differ in shape"):
        metrics.psnr(rng.random((4, 4, 3)), rng.random((4, 5, 3)))


@pytest.mark.parametrize("size", [(160, 90), (17, 33)])
def test_gpu_reduction_equals_numpy(ctx, rng, size):
    a = rng.uniform(-0.2, 1.2, (size[1], size[0], 4)).astype(np.float32)
    b = rng.uniform(-0.2, 1.2, (size[1], size[0], 4)).astype(np.float32)
    gpu = metrics.gpu_mse(ctx, ctx.upload(a), ctx.upload(b))
    assert gpu == pytest.approx(metrics.mse(a, b), rel=1e-5)


def test_tile_border_error_finds_errors_on_the_tile_grid(rng):
    k = 8
    reference = 0.2 + 0.6 * rng.random((48, 64, 3))  # no clipping below
    noisy = reference + rng.normal(0, 0.01, reference.shape)  # the same everywhere
    even = metrics.tile_border_error(reference, np.clip(noisy, 0, 1), k)
    assert 0.8 < even["ratio"] < 1.25 and 0.8 < even["step_ratio"] < 1.25
    blocky = reference.copy()
    for i in range(0, 48, k):  # each tile off by its own constant: seams at tile borders only
        for j in range(0, 64, k):
            blocky[i : i + k, j : j + k] += rng.uniform(-0.05, 0.05)
    seams = metrics.tile_border_error(reference, np.clip(blocky, 0, 1), k)
    assert seams["step_ratio"] > 100  # inside the tiles the error does not jump
    border = np.zeros((48, 64), bool)
    border[:, 7:9] = border[:, 15:17] = True  # errors on two tile borders, one pixel each side
    lines = reference.copy()
    lines[border] = np.clip(lines[border] + 0.2, 0, 1)
    result = metrics.tile_border_error(reference, lines, k)
    assert result["interior"] == 0 and result["ratio"] == np.inf


def test_tile_border_error_counts_border_pixels_and_rejects_bad_tiles():
    reference = np.zeros((10, 12, 3))
    test = reference.copy()
    test[:, 3:5] = 1  # the columns either side of the border x = 4
    result = metrics.tile_border_error(reference, test, 4)
    # borders x = 4, 8 and y = 4, 8; one pixel each side: rows and columns 3, 4, 7, 8
    assert result["border_pixels"] == 4 * 12 + 4 * 10 - 16
    assert result["border"] == pytest.approx(20 / 72) and result["interior"] == 0
    with pytest.raises(ValueError, match="k must be an integer >= 2"):
        metrics.tile_border_error(reference, test, 1)
    with pytest.raises(ValueError, match="band must be an integer in 1..k/2"):
        metrics.tile_border_error(reference, test, 4, band=3)
    with pytest.raises(ValueError, match="no tile border"):
        metrics.tile_border_error(reference, test, 16)
