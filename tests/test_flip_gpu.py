"""gpu_flip (shaders/passes/flip_horizontal.comp, flip_error.comp; docs/spec.md §6.1) against the
flip-evaluator package (metrics.flip, on the same images in sRGB) and against its NumPy twin
blurlab.twins.flip: the study's frames (every built-in scene blurred by four methods, and
unblurred, against its reference), random and noisy images, and sizes smaller than the filters.
The issue's bars: the mean within 1e-3 of flip-evaluator on >= 20 pairs, the per-pixel map
within 1e-2 on >= 99 % of pixels."""

from __future__ import annotations

import flip_evaluator
import numpy as np
import pytest
from method_picks import pick, picks

import blurlab as bl
from blurlab import metrics
from blurlab.io.images import linear_to_srgb
from blurlab.methods.tile_filter import FILTER_OPTIONS
from blurlab.twins import flip as twin

SIZE = (160, 90)
# The reconstruction filters with the tile-filter options, a plain gather and no blur (None).
FILTERS = tuple(picks(kind="filter", params=tuple(FILTER_OPTIONS)))
GATHER = pick(kind="gather", params=("taps",))
STUDY_METHODS = (*FILTERS, GATHER, None)
# Measured on llvmpipe over the 25 pairs below (2026-11-23): means at most 1.7e-5 apart from
# flip-evaluator (the 1x1 image; study frames 8.4e-6), pixels at most 8.6e-5 (float32 on both
# sides, sums in another order). The bounds keep a margin of 5-10x.
MEAN_TOLERANCE = 1e-4
PIXEL_TOLERANCE = 1e-3


def evaluator_map(reference: np.ndarray, test: np.ndarray) -> np.ndarray:
    """flip-evaluator's LDR map of two linear images (encoded to sRGB, as metrics.flip does)."""
    srgb = lambda c: np.ascontiguousarray(linear_to_srgb(c[..., :3]), np.float32)  # noqa: E731
    error, _, _ = flip_evaluator.evaluate(
        srgb(reference), srgb(test), "LDR", inputsRGB=True, applyMagma=False
    )
    return np.squeeze(error)


def agree(ctx, reference: np.ndarray, test: np.ndarray) -> float:
    ref_texture, test_texture = ctx.upload(reference), ctx.upload(test)
    mean = metrics.gpu_flip(ctx, ref_texture, test_texture)
    gpu_map = metrics.gpu_flip_map(ctx, ref_texture, test_texture)
    expected = evaluator_map(reference, test)
    assert mean == pytest.approx(metrics.flip(reference, test), abs=MEAN_TOLERANCE)
    assert mean == pytest.approx(float(expected.mean()), abs=MEAN_TOLERANCE)
    assert np.abs(gpu_map - expected).max() <= PIXEL_TOLERANCE
    assert mean == pytest.approx(float(gpu_map.astype(np.float64).mean()), abs=1e-6)
    return mean


@pytest.fixture(scope="module")
def study_frames(ctx):
    """(scene, method, reference, blurred) for every built-in scene at 160x90."""
    pairs = []
    for name in bl.scenes.names():
        scene = bl.scenes.get(name)
        reference = ctx.reference(scene, SIZE, samples=32, progress=False).color
        for method in STUDY_METHODS:
            frame = ctx.render(scene, SIZE, instant=bl.method_instant(method or GATHER, {}))
            test = frame.color if method is None else bl.blur(ctx, frame, method).color
            pairs.append((name, method, reference, test))
    return pairs


def test_study_frames_equal_flip_evaluator(ctx, study_frames):
    assert len(study_frames) >= 20
    means = [agree(ctx, reference, test) for _, _, reference, test in study_frames]
    assert all(0.0 < m < 1.0 for m in means)
    # The reconstruction filters bring every scene closer to its reference than the sharp frame.
    by_pair = {(name, method): m for (name, method, *_), m in zip(study_frames, means, strict=True)}
    for name, method in by_pair:
        if method in FILTERS:
            assert by_pair[name, method] < by_pair[name, None], (name, method)


@pytest.mark.parametrize("size", [(160, 90), (17, 33), (64, 1), (3, 2), (1, 1)])
def test_random_images_equal_flip_evaluator(ctx, rng, size):
    a = rng.uniform(-0.2, 1.2, (size[1], size[0], 4)).astype(np.float32)
    b = (a + rng.normal(0.0, 0.1, a.shape)).astype(np.float32)
    agree(ctx, a, b)


def test_gpu_equals_the_numpy_twin(ctx, rng):
    a = rng.uniform(0.0, 1.0, (36, 64, 4)).astype(np.float32)
    b = np.clip(a + rng.normal(0.0, 0.05, a.shape), 0, 1).astype(np.float32)
    gpu_map = metrics.gpu_flip_map(ctx, ctx.upload(a), ctx.upload(b))
    assert np.abs(gpu_map - twin.flip_map(a, b)).max() < 1e-4


def test_identical_images_give_zero(ctx, rng):
    a = ctx.upload(rng.uniform(0.0, 1.0, (36, 64, 4)).astype(np.float32))
    # Exactly 0 on llvmpipe; NVIDIA's compiler may contract the two images' identical
    # arithmetic differently (8.2e-7 measured on the H100), far below what FLIP resolves.
    assert metrics.gpu_flip(ctx, a, a) <= 1e-5


def test_black_against_white_is_near_one(ctx):
    black = np.zeros((36, 64, 4), np.float32)
    white = np.ones((36, 64, 4), np.float32)
    assert agree(ctx, black, white) > 0.9


def test_pixels_per_degree_change_the_filters(ctx, rng):
    a = ctx.upload(rng.uniform(0.0, 1.0, (36, 64, 4)).astype(np.float32))
    b = ctx.upload(rng.uniform(0.0, 1.0, (36, 64, 4)).astype(np.float32))
    near, far = metrics.gpu_flip(ctx, a, b, ppd=20.0), metrics.gpu_flip(ctx, a, b, ppd=120.0)
    # Seen from farther away (more pixels per degree) pixel noise blurs together.
    assert far < near


def test_nan_and_infinite_colours_read_as_the_passes_read_them(ctx, rng):
    a = rng.uniform(0.0, 1.0, (36, 64, 4)).astype(np.float32)
    b = a.copy()
    b[5, 7], b[20, 30], b[30, 60] = np.nan, np.inf, -np.inf
    expected = b.copy()
    expected[5, 7], expected[20, 30], expected[30, 60] = 0.0, 1.0, 0.0  # NaN as 0, then clipped
    gpu_map = metrics.gpu_flip_map(ctx, ctx.upload(a), ctx.upload(b))
    assert np.isfinite(gpu_map).all()
    assert np.abs(gpu_map - twin.flip_map(a, expected)).max() < 1e-4


def test_bad_input_is_rejected(ctx):
    a = ctx.upload(np.zeros((36, 64, 4), np.float32))
    b = ctx.upload(np.zeros((36, 63, 4), np.float32))
    with pytest.raises(ValueError, match=r"\(36, 64, 4\) and \(36, 63, 4\)"):
        metrics.gpu_flip(ctx, a, b)
    with pytest.raises(ValueError, match="ppd"):
        metrics.gpu_flip(ctx, a, a, ppd=0)
    with pytest.raises(ValueError, match="RGB"):
        gray = ctx.upload(np.zeros((36, 64), np.float32))
        metrics.gpu_flip(ctx, gray, gray)


# --- HDR-FLIP (shaders/passes/hdr_flip_tonemap.comp, hdr_flip_worst.comp; docs/spec.md §6.2)


def hdr_pairs(ctx, rng) -> list[tuple[np.ndarray, np.ndarray]]:
    """Linear HDR pairs: the HDR scenes at 160x90 blurred against their references, random
    images spanning several stops, a bright spot, and a black reference."""
    pairs = []
    for name in bl.scenes.names("hdr"):
        scene = bl.scenes.get(name)
        reference = ctx.reference(scene, SIZE, samples=16, progress=False).color
        blurred = bl.blur(ctx, ctx.render(scene, SIZE), FILTERS[0]).color
        pairs.append((reference, blurred))
    for scale in (1.0, 50.0, 4000.0):
        a = (rng.random((45, 80, 4)) ** 3 * scale).astype(np.float32)
        b = np.clip(a * (1 + 0.3 * rng.standard_normal(a.shape)), 0, None).astype(np.float32)
        pairs.append((a, b))
    spot = np.full((36, 64, 4), 0.2, np.float32)
    spot[10:14, 20:30, :3] = 500.0
    pairs.append((spot, np.roll(spot, 3, axis=1)))
    pairs.append((np.zeros((20, 30, 4), np.float32), np.full((20, 30, 4), 0.5, np.float32)))
    return pairs


def test_gpu_hdr_flip_equals_flip_evaluator(ctx, rng):
    """gpu_hdr_flip against flip-evaluator's HDR mode (metrics.hdr_flip): within the metric's
    registered tolerance on every pair. Measured on llvmpipe: at most 3e-7 apart."""
    pairs = hdr_pairs(ctx, rng)
    assert len(pairs) >= 8
    tolerance = metrics.get("hdr_flip").tolerance
    for reference, test in pairs:
        expected = metrics.hdr_flip(reference, test)
        got = metrics.gpu_hdr_flip(ctx, ctx.upload(reference), ctx.upload(test))
        assert got == pytest.approx(expected, abs=tolerance)


def test_gpu_hdr_flip_of_identical_images_is_zero_and_ranges_agree(ctx, rng):
    image = (rng.random((30, 40, 4)) * 20).astype(np.float32)
    texture = ctx.upload(image)
    assert metrics.gpu_hdr_flip(ctx, texture, texture) == 0.0
    other = ctx.upload(np.clip(image * 1.5, 0, None))
    passed = metrics.gpu_hdr_flip(
        ctx, texture, other, exposure_range=metrics.flip_exposure_range(image)
    )
    assert passed == metrics.gpu_hdr_flip(ctx, texture, other)


def test_hdr_flip_exposures_are_flip_evaluators_count():
    assert metrics.hdr_flip_exposures(-3.0, 2.5) == pytest.approx(
        [-3.0 + i * 5.5 / 5 for i in range(6)]
    )
    assert metrics.hdr_flip_exposures(0.0, 0.0) == [0.0, 0.0]  # at least two


def test_gpu_hdr_flip_refuses_what_it_cannot_compare(ctx):
    a, b = ctx.upload(np.zeros((8, 8, 4), np.float32)), ctx.upload(np.zeros((8, 9, 4), np.float32))
    with pytest.raises(ValueError, match="gpu_hdr_flip"):
        metrics.gpu_hdr_flip(ctx, a, b)
    with pytest.raises(ValueError, match="finite"):
        metrics.gpu_hdr_flip(ctx, a, a, exposure_range=(0.0, float("nan")))
