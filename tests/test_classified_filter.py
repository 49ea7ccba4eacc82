"""reconstruct_mcguire2012 with classify=True (docs/classify_and_steps.md): the classified
image against bl.twins.classify.classified and against the unclassified filter class by
class, and the filter's invariants with classification on."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_inside_input_range, random_frame
from test_classify_tiles import structured_motion

import blurlab as bl
from blurlab.methods.core import twin_keywords
from blurlab.twins import classify as ref
from blurlab.twins import mcguire2012 as m

FILTER = "reconstruct_mcguire2012"


def per_pixel(classes, k, shape):
    return np.kron(classes, np.ones((k, k)))[: shape[0], : shape[1]].astype(int)


@pytest.mark.parametrize(("k", "samples", "size"), [(10, 15, (160, 90)), (7, 8, (97, 61))])
def test_random_frames_match_reference(ctx, rng, k, samples, size):
    frame = structured_motion(rng, *size, k)
    params = {"k": k, "samples": samples, "soft_z": 0.5, "seed": 3, "uniform_spread": 0.5}
    out = bl.blur(ctx, frame, FILTER, classify=True, **params)
    values = bl.method(FILTER).defaults(frame, **params)
    taken = {key: values[key] for key in ("k", "samples", "exposure", "seed", "uniform_spread")}
    full = m.reconstruct_mcguire2012(
        frame.color,
        frame.depth,
        frame.motion,
        **{key: values[key] for key in twin_keywords(m.reconstruct_mcguire2012)},
    )
    expected, classes = ref.classified(frame.color, frame.depth, frame.motion, full, **taken)
    np.testing.assert_array_equal(out.buffers["tile_class"], classes)
    assert np.bincount(classes.ravel(), minlength=3).min() > 0  # every class ran
    error = np.abs(out.color - expected)
    assert (error.max(axis=-1) <= 1e-3).mean() >= 0.999
    assert error.mean() <= 1e-4


@pytest.mark.parametrize(
    ("scene", "size", "k"), [("mostly_still", (320, 180), 10), ("teapot_pass", (160, 90), 12)]
)
def test_each_class_gives_what_it_promises(ctx, scene, size, k):
    frame = ctx.render(bl.scenes.get(scene), size)
    plain = bl.blur(ctx, frame, FILTER, k=k).color
    result = bl.blur(ctx, frame, FILTER, k=k, classify=True)
    classes = per_pixel(result.buffers["tile_class"], k, frame.color.shape)
    out = result.color
    still, uniform, full = (classes == c for c in range(3))
    assert still.any() and full.any()
    assert out[full].tobytes() == plain[full].tobytes()  # the same pass, the same bits
    assert out[still].tobytes() == frame.color[still].tobytes()
    if scene == "mostly_still":  # the card's inside moves uniformly at one depth
        assert uniform.any()
        assert np.abs(out[uniform] - plain[uniform]).max() <= 1e-5


def test_loose_uniform_spread_stays_close_to_the_full_filter(ctx):
    """camera_yaw at uniform_spread = 2 px: the tiles classed uniform there move by up to
    4 px apart at several depths. Measured on llvmpipe: max 0.106, mean 0.0044."""
    frame = ctx.render(bl.scenes.get("camera_yaw"), (160, 90))
    plain = bl.blur(ctx, frame, FILTER, k=10).color
    result = bl.blur(ctx, frame, FILTER, k=10, classify=True, uniform_spread=2.0)
    uniform = per_pixel(result.buffers["tile_class"], 10, frame.color.shape) == 1
    assert uniform.mean() > 0.1
    difference = np.abs(result.color - plain)[uniform][:, :3]
    assert difference.mean() <= 0.006 and difference.max() <= 0.15


def test_mostly_still_error_within_a_tenth_of_a_db(ctx):
    scene = bl.scenes.get("mostly_still")
    frame = ctx.render(scene, (320, 180))
    reference = ctx.reference(scene, (320, 180), samples=64, progress=False)
    plain = bl.blur(ctx, frame, FILTER, k=10).color
    classified = bl.blur(ctx, frame, FILTER, k=10, classify=True).color
    psnr = bl.metrics.psnr
    assert abs(psnr(reference.color, plain) - psnr(reference.color, classified)) <= 0.1


def test_still_image_comes_back_unchanged(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = 0
    result = bl.blur(ctx, frame, FILTER, classify=True)
    assert result.color.tobytes() == frame.color.tobytes()
    assert not result.buffers["tile_class"].any()


def test_output_stays_inside_the_input_range(ctx, rng):
    frame = structured_motion(rng, 120, 80, 10)
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25
    out = bl.blur(ctx, frame, FILTER, k=10, classify=True, uniform_spread=1.0).color
    assert_inside_input_range(out, frame.color)


@pytest.mark.parametrize("scale", [0.0, 1e30])
def test_zero_and_huge_motion_give_no_nan(ctx, rng, scale):
    frame = random_frame(rng, 80, 60)
    frame.motion[:] = np.float32(scale) * np.sign(frame.motion)
    result = bl.blur(ctx, frame, FILTER, k=8, classify=True)
    assert np.isfinite(result.color).all()
    assert np.isfinite(result.buffers["tile_bounds"]).all()


def test_same_seed_same_bits(ctx, rng):
    frame = structured_motion(rng, 96, 64, 8)
    a = bl.blur(ctx, frame, FILTER, k=8, seed=3, classify=True, uniform_spread=1.0)
    b = bl.blur(ctx, frame, FILTER, k=8, seed=3, classify=True, uniform_spread=1.0)
    assert a.color.tobytes() == b.color.tobytes()
    assert a.buffers["tile_class"].tobytes() == b.buffers["tile_class"].tobytes()


def test_timings_name_every_pass(ctx, rng):
    result = bl.blur(ctx, random_frame(rng, 64, 36), FILTER, classify=True)
    assert list(result.timings) == [
        "tile_max",
        "neighbor_max",
        "classify_tiles",
        "still_copy",
        "uniform_gather",
        "reconstruct",
    ]


@pytest.mark.parametrize(
    ("params", "error", "message"),
    [
        ({"classify": "yes"}, TypeError, "classify must be True or False"),
        (
            {"classify": True, "uniform_spread": -1.0},
            ValueError,
            r"uniform_spread = -1.0 is outside \[0, 512\]",
        ),
        ({"classify": True, "backend": "fragment"}, ValueError, "compute backend"),
    ],
)
def test_bad_input_is_named(ctx, rng, params, error, message):
    with pytest.raises(error, match=message):
        bl.blur(ctx, random_frame(rng, 16, 16), FILTER, **params)


def test_classify_is_off_by_default(ctx, rng):
    result = bl.blur(ctx, random_frame(rng, 32, 32), FILTER)
    assert result.params["classify"] is False and "tile_class" not in result.buffers


@pytest.mark.parametrize(
    "option", [{"jitter_tiles": 1}, {"adaptive_samples": 1}, {"early_exit": 2.0}]
)
def test_classification_refuses_the_filter_options(ctx, option):
    frame = bl.Frame(
        np.zeros((32, 32, 4), np.float32), np.ones((32, 32), np.float32), np.ones((32, 32, 2))
    )
    with pytest.raises(ValueError, match=f"classify=True takes none of .*{next(iter(option))}"):
        bl.blur(ctx, frame, "reconstruct_mcguire2012", classify=True, **option)
