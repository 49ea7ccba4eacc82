"""SsimReductionPass (shaders/passes/ssim.comp) against its NumPy twins metrics.ssim and mse
(docs/spec.md §6): random images, rendered frames, near-flat images (where float32 variances
cancel), sizes that are not multiples of any work-group tile and sizes smaller than the 11-tap
window; gpu_mse_ssim (SSIM and squared error from one dispatch) against gpu_mse and gpu_ssim,
in every work-group layout (metrics.SSIM_LAYOUTS: the 32-pixel tiles of ssim.comp and the
strips of ssim_strip.comp), with NaN and infinite colours."""

from __future__ import annotations

import numpy as np
import pytest
from method_picks import EXAMPLE

import blurlab as bl
from blurlab import _core, metrics

# Measured on llvmpipe: at most 5.4e-7 apart on every image below with 16 x 16 work groups,
# 2.4e-7 with today's 32 x 16 (float32 sums of 121 taps against float64; the rendered frame's
# dark pixels, where C1 dominates, and the smallest images, whose means average the least, show
# the largest gaps). The bound keeps a margin of
# about 10x and is 2x tighter than sweeps need (1e-5).
TOLERANCE = 5e-6


LAYOUTS = list(metrics.SSIM_LAYOUTS)


def agree(ctx, a: np.ndarray, b: np.ndarray, layout: str, tolerance: float = TOLERANCE) -> float:
    gpu = metrics.gpu_ssim(ctx, ctx.upload(a), ctx.upload(b), layout=layout)
    assert gpu == pytest.approx(metrics.ssim(a, b), abs=tolerance)
    return gpu


def noisy_pair(rng, height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """A random image with values outside [0, 1] (clipped by both) and a noisy copy."""
    a = rng.uniform(-0.2, 1.2, (height, width, 4)).astype(np.float32)
    b = (a + rng.normal(0.0, 0.1, a.shape)).astype(np.float32)
    return a, b


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("size", [(160, 90), (17, 33), (16, 16), (33, 1), (1, 70), (300, 70)])
def test_random_images_equal_numpy(ctx, rng, size, layout):
    # 300 x 70: more than one strip of every width across, cut strips on two edges; 1 x 70: a
    # column mirrored onto itself, several strips down.
    a, b = noisy_pair(rng, size[1], size[0])
    assert agree(ctx, a, b, layout) < 0.99


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("size", [(1, 1), (2, 3), (5, 4), (7, 1), (11, 11)])
def test_images_smaller_than_the_window_mirror_as_numpy_does(ctx, rng, size, layout):
    # np.pad(mode="reflect") repeats the mirror with period 2(n - 1) when n <= radius; the
    # shader's reflect_index does the same, so tiny images need no special case.
    a, b = noisy_pair(rng, size[1], size[0])
    agree(ctx, a, b, layout)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_smooth_bright_images_keep_their_variance(ctx, layout):
    # Luminance 0.9 ± 0.03, varying smoothly: E[x²] - E[x]² cancels about three digits in
    # float32. The shader takes the moments about the luminance at its tile's center; measured
    # 3e-9 from NumPy that way, 2e-6 without the shift (the rendered frame below: 5e-7 with
    # the shift, 6e-5 without).
    y, x = np.mgrid[0:90, 0:160].astype(np.float64)
    a = 0.9 + 0.03 * np.sin(x / 7) * np.cos(y / 5)
    b = 0.9 + 0.03 * np.sin(x / 6 + 1) * np.cos(y / 4)
    gray = lambda v: np.repeat(v[..., None], 4, axis=-1).astype(np.float32)  # noqa: E731
    assert agree(ctx, gray(a), gray(b), layout, tolerance=2e-7) < 0.95


@pytest.fixture(scope="module")
def rendered_pair(ctx):
    """fan at 160 x 90, blurred, and its reference: dark and bright regions side by side, where
    the shift of the moments matters. Measured on llvmpipe: tiles within 9.7e-7 of NumPy,
    strips within 4.2e-7 (with one shift per strip instead of per column: 6.9e-6)."""
    scene = bl.scenes.fan()
    frame = ctx.render(scene, (160, 90))
    blurred = bl.blur(ctx, frame, EXAMPLE, timed=False)
    reference = ctx.reference(scene, (160, 90), samples=16, progress=False)
    return reference, blurred.textures["color"].download()


@pytest.mark.parametrize("layout", LAYOUTS)
def test_rendered_frame_against_its_reference(ctx, rendered_pair, layout):
    reference, color = rendered_pair
    gpu = metrics.gpu_ssim(ctx, reference.texture, ctx.upload(color), layout=layout)
    numpy = metrics.ssim(reference.color, color)
    assert gpu == pytest.approx(numpy, abs=TOLERANCE)
    assert 0.0 < gpu < 1.0
    prepared = metrics.prepare_reference(ctx, reference.texture, layout)
    mse, ssim = metrics.gpu_mse_ssim(ctx, prepared, ctx.upload(color))
    prepared.release()
    assert mse == pytest.approx(metrics.mse(reference.color, color), rel=MSE_REL)
    assert ssim == pytest.approx(numpy, abs=TOLERANCE)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_identical_images_give_one(ctx, rng, layout):
    a, _ = noisy_pair(rng, 36, 64)
    texture = ctx.upload(a)
    assert metrics.gpu_ssim(ctx, texture, texture, layout=layout) == pytest.approx(1.0, abs=1e-6)


# The squared error: float32 sums of at most 32 x 32 pixels per work group (each term < 3),
# added in double, against NumPy's float64. Measured on llvmpipe at most 8.8e-8 relative on the
# images below and a 640 x 360 pair, every layout; the SSIM of the fused call is bit for bit
# that of gpu_ssim (the same shader less the squared error) and within 1.8e-7 of NumPy. The
# bound keeps a margin of 100x, as tests/test_metrics.py holds gpu_mse.
MSE_REL = 1e-5


def fused_agrees(ctx, a: np.ndarray, b: np.ndarray, layout: str | None = None) -> tuple:
    """gpu_mse_ssim of a and b equals gpu_mse, gpu_ssim and the NumPy mse and ssim."""
    ta, tb = ctx.upload(a), ctx.upload(b)
    mse, ssim = metrics.gpu_mse_ssim(ctx, ta, tb, layout=layout)
    assert mse == pytest.approx(metrics.gpu_mse(ctx, ta, tb), rel=MSE_REL)
    assert mse == pytest.approx(metrics.mse(a, b), rel=MSE_REL)
    assert ssim == pytest.approx(metrics.gpu_ssim(ctx, ta, tb, layout=layout), abs=TOLERANCE)
    assert ssim == pytest.approx(metrics.ssim(a, b), abs=TOLERANCE)
    return mse, ssim


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("size", [(160, 90), (17, 33), (33, 1), (1, 1), (2, 3), (11, 11)])
def test_fused_mse_and_ssim_equal_the_separate_calls_and_numpy(ctx, rng, size, layout):
    a, b = noisy_pair(rng, size[1], size[0])
    mse, ssim = fused_agrees(ctx, a, b, layout)
    assert mse > 0 and ssim < 1.0


@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_work_group_layout_gives_the_numpy_values(ctx, rng, layout):
    # 70 x 45: no layout's tile divides it, so every layout has cut tiles on two edges.
    a, b = noisy_pair(rng, 45, 70)
    fused_agrees(ctx, a, b, layout)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_identical_images_give_zero_error_and_ssim_one(ctx, rng, layout):
    a, _ = noisy_pair(rng, 36, 64)
    texture = ctx.upload(a)
    mse, ssim = metrics.gpu_mse_ssim(ctx, texture, texture, layout=layout)
    assert mse == 0.0 and ssim == pytest.approx(1.0, abs=1e-6)
    prepared = metrics.prepare_reference(ctx, texture, layout)
    mse, ssim = metrics.gpu_mse_ssim(ctx, prepared, texture)
    prepared.release()
    assert mse == 0.0 and ssim == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_nan_and_infinite_colours_read_as_the_passes_read_them(ctx, rng, layout):
    # NaN reads as 0 (common/inputs.glsl), then colour clips to [0, 1]: +inf as 1, -inf as 0.
    a, b = noisy_pair(rng, 36, 64)
    b[5, 7, 0], b[20, 30, 1], b[30, 60] = np.nan, np.inf, -np.inf
    a[10, 3, 2] = np.nan
    clean = lambda image: np.nan_to_num(image, nan=0.0, posinf=1.0, neginf=0.0)  # noqa: E731
    ta, tb = ctx.upload(a), ctx.upload(b)
    mse, ssim = metrics.gpu_mse_ssim(ctx, ta, tb, layout=layout)
    assert np.isfinite([mse, ssim]).all()
    assert mse == pytest.approx(metrics.mse(clean(a), clean(b)), rel=MSE_REL)
    assert ssim == pytest.approx(metrics.ssim(clean(a), clean(b)), abs=TOLERANCE)
    assert metrics.gpu_mse(ctx, ta, tb) == pytest.approx(mse, rel=MSE_REL)
    assert metrics.gpu_ssim(ctx, ta, tb, layout=layout) == pytest.approx(ssim, abs=TOLERANCE)
    prepared = metrics.prepare_reference(ctx, ta, layout)
    assert metrics.gpu_mse_ssim(ctx, prepared, tb) == pytest.approx((mse, ssim), abs=TOLERANCE)
    prepared.release()


@pytest.mark.parametrize("name", ["gpu_ssim", "gpu_mse_ssim"])
def test_bad_textures_and_layouts_are_rejected(ctx, name):
    measure = getattr(metrics, name)
    wide, narrow = (ctx.upload(np.zeros((36, w, 4), np.float32)) for w in (64, 63))
    with pytest.raises(ValueError, match=rf"{name}: .*\(36, 64, 4\) and \(36, 63, 4\)"):
        measure(ctx, wide, narrow)
    gray = ctx.upload(np.zeros((36, 64), np.float32))
    with pytest.raises(ValueError, match="need RGB"):
        measure(ctx, gray, gray)
    with pytest.raises(ValueError, match="unknown SSIM layout 'square'; choose from"):
        measure(ctx, wide, wide, layout="square")


@pytest.mark.parametrize("tile_rows, rows", [(12, 4), (16, 3), (8, 16), (0, 1)])
def test_the_pass_refuses_layouts_its_shader_cannot_tile(ctx, tile_rows, rows):
    with pytest.raises(ValueError, match="tile_rows must be 8, 16 or 32"):
        _core.SsimReductionPass(ctx.native, tile_rows, rows)


@pytest.mark.parametrize(
    "columns, tile_rows, rows",
    [(64, 16, 4), (128, 8, 8), (128, 64, 64), (512, 16, 16), (48, 16, 16)],
)
def test_the_pass_refuses_strips_its_shader_cannot_walk(ctx, columns, tile_rows, rows):
    # A strip's invocation walks its whole column: rows per invocation must be the strip's.
    with pytest.raises(ValueError, match="strips .* need tile_rows 16 or 32"):
        _core.SsimReductionPass(ctx.native, tile_rows, rows, columns)


@pytest.mark.parametrize("size", [(160, 90), (17, 33), (33, 1), (1, 1), (11, 11)])
def test_a_prepared_reference_gives_the_values_of_the_pair(ctx, rng, size):
    # Every layout: the prepare pass and the three-moment pass tile alike.
    a, b = noisy_pair(rng, size[1], size[0])
    a[2 % size[1], 0, 1] = np.nan  # read as 0, as the unprepared pass reads it
    ta, tb = ctx.upload(a), ctx.upload(b)
    clean = np.nan_to_num(a, nan=0.0)
    for layout in metrics.SSIM_LAYOUTS:
        prepared = metrics.prepare_reference(ctx, ta, layout)
        mse, ssim = metrics.gpu_mse_ssim(ctx, prepared, tb)
        assert mse == pytest.approx(metrics.mse(clean, b), rel=MSE_REL)
        assert ssim == pytest.approx(metrics.ssim(clean, b), abs=TOLERANCE)
        assert (mse, ssim) == pytest.approx(metrics.gpu_mse_ssim(ctx, ta, tb, layout=layout))
        # It holds copies: overwriting the reference's texture does not change its values.
        ta.upload(b)
        assert metrics.gpu_mse_ssim(ctx, prepared, tb) == (mse, ssim)
        ta.upload(a)
        prepared.release()
    with pytest.raises(ValueError, match="after release"):
        metrics.gpu_mse_ssim(ctx, prepared, tb)


def test_a_prepared_reference_refuses_another_size_and_no_colour(ctx, rng):
    a, b = noisy_pair(rng, 36, 64)
    prepared = metrics.prepare_reference(ctx, ctx.upload(a))
    with pytest.raises(ValueError, match=r"gpu_mse_ssim: .*\(36, 64, 4\) and \(36, 63, 4\)"):
        metrics.gpu_mse_ssim(ctx, prepared, ctx.upload(b[:, :63]))
    with pytest.raises(ValueError, match="RGB"):
        metrics.prepare_reference(ctx, ctx.upload(np.zeros((36, 64), np.float32)))
    with pytest.raises(ValueError, match="unknown SSIM layout"):
        metrics.prepare_reference(ctx, ctx.upload(a), layout="square")
