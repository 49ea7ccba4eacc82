"""The antialiased reference (docs/spec.md §11) and sub-pixel jitter of the G-buffer (§12)."""

from __future__ import annotations

import numpy as np
import pytest
from test_reference import square_scene

import blurlab as bl
from blurlab.scene import sampling
from blurlab.twins import projection

SIZE = (160, 90)


def still_scene() -> bl.Scene:
    """A tilted box and a sphere, Lambert-shaded, nothing moving: every edge is a still edge."""
    camera = bl.Camera((0.3, 0.4, 4.0), (0, 0, 0), fov_y=40)
    scene = bl.Scene(camera, background=(0.1, 0.1, 0.2, 1))
    tilt = bl.quaternion((0.3, 1.0, 0.2), 0.7)
    scene.add(
        bl.mesh.box((1.0, 0.8, 0.6)),
        bl.Material((0.9, 0.5, 0.2)),
        bl.Motion.static((-0.5, 0, 0), rotation=tilt),
    )
    scene.add(bl.mesh.sphere(0.5), bl.Material((0.2, 0.8, 0.4)), bl.Motion.static((0.7, 0.1, 0.3)))
    return scene


@pytest.mark.parametrize("m", [4, 7, 10])
def test_positions_are_a_net_and_times_are_stratified(m):
    n = 1 << m
    times, positions = sampling.shutter_samples((0.0, 1.0), n, seed=3)
    np.testing.assert_array_equal(np.floor(times * n), np.arange(n))
    for j in range(m + 1):  # one point in every 2^-j x 2^-(m-j) box: a (0, m, 2)-net
        cells = np.floor(positions[:, 0] * 2**j) * 2 ** (m - j) + np.floor(
            positions[:, 1] * 2 ** (m - j)
        )
        assert len(np.unique(cells)) == n


def test_any_n_has_one_time_per_stratum():
    times, positions = sampling.shutter_samples((2.0, 3.0), 1000, seed=0)
    np.testing.assert_array_equal(np.floor((times - 2.0) * 1000), np.arange(1000))
    assert positions.shape == (1000, 2) and 0 <= positions.min() and positions.max() < 1


def test_sobol_direction_numbers_are_joe_kuo():
    v = sampling.direction_numbers(2)[:6] >> np.arange(31, 25, -1).astype(np.uint32)
    np.testing.assert_array_equal(v, [1, 3, 3, 9, 29, 23])


def test_seeds_scramble_differently_and_repeat():
    a = sampling.scrambled_sobol(256, 1)
    np.testing.assert_array_equal(a, sampling.scrambled_sobol(256, 1))
    assert np.abs(a - sampling.scrambled_sobol(256, 2)).mean() > 0.1


def test_integer_jitter_shifts_the_image_by_whole_pixels(ctx):
    scene = still_scene()
    plain = ctx.render(scene, SIZE).color
    shifted = ctx.render(scene, SIZE, jitter=(2.0, -1.0)).color
    # pixel (x, y) of the shifted image shows the plain image at (x - 2, y + 1)
    same = np.abs(shifted[:-1, 2:] - plain[1:, :-2]).max(axis=-1) < 1e-5
    assert same.mean() > 0.999
    # motion is a difference of two equally shifted positions: unchanged where the same
    # surface is seen
    jittered = ctx.render(bl.scenes.fan(), SIZE, jitter=(0.25, 0.5))
    centered = ctx.render(bl.scenes.fan(), SIZE)
    same_object = jittered.object_id == centered.object_id
    difference = np.abs(jittered.motion - centered.motion).max(axis=-1)[same_object]
    assert np.median(difference) < 0.02 and difference.mean() < 0.5


@pytest.mark.parametrize("jitter", [(0.5,), "ab", (np.nan, 0.0), (0.0, np.inf), (True, 0.0)])
def test_bad_jitter(ctx, jitter):
    with pytest.raises(ValueError, match="jitter"):
        ctx.render(still_scene(), SIZE, jitter=jitter)


def test_still_scene_equals_the_box_filtered_supersampled_image(ctx):
    size, k = (40, 24), 32
    scene = still_scene()
    big = ctx.render(scene, (size[0] * k, size[1] * k)).color
    supersampled = big.reshape(size[1], k, size[0], k, 4).mean(axis=(1, 3))
    antialiased = ctx.reference(scene, size, samples=1024, antialias=True).color
    centers = ctx.reference(scene, size, samples=1).color
    assert bl.metrics.psnr(antialiased, supersampled) > 65  # measured 73.4 dB
    assert np.abs(antialiased - supersampled).max() < 0.02
    assert bl.metrics.psnr(centers, supersampled) < 40  # pixel centers alias: measured 32.3 dB


def box_filtered_square(scene, size) -> np.ndarray:
    """The square's coverage of each pixel's area over the shutter, integrated densely."""
    camera = scene.camera
    corners = np.array([[-0.5, -0.5, 0.0], [0.5, 0.5, 0.0]])
    ends = [
        projection.project(corners + scene.objects[0].model(t)[:3, 3], camera, t, size)[0]
        for t in (0.0, 1.0)
    ]
    top, bottom = sorted(ends[0][:, 1])
    y = np.arange(size[1])
    rows = np.clip(np.minimum(y + 1, bottom) - np.maximum(y, top), 0, 1)
    s = np.linspace(0, 1, 20001)[:, None]
    left = ends[0][0, 0] + (ends[1][0, 0] - ends[0][0, 0]) * s
    right = ends[0][1, 0] + (ends[1][1, 0] - ends[0][1, 0]) * s
    x = np.arange(size[0])
    columns = np.clip(np.minimum(x + 1, right) - np.maximum(x, left), 0, 1).mean(axis=0)
    return rows[:, None] * columns[None, :]


def test_moving_square_converges_to_its_box_filtered_coverage(ctx):
    scene = square_scene(distance_px=30.0)
    expected = box_filtered_square(scene, SIZE)
    errors = []
    for n in (16, 256):
        reference = ctx.reference(scene, SIZE, samples=n, antialias=True, seed=1)
        errors.append(np.sqrt(np.mean((reference.color[..., 0] - expected) ** 2)))
    assert errors[1] < errors[0] / 3
    assert errors[1] < 2e-3
    temporal = ctx.reference(scene, SIZE, samples=256).color[..., 0]
    assert np.sqrt(np.mean((temporal - expected) ** 2)) > 5 * errors[1]  # still edges alias


def test_seed_repeats_and_changes_the_noise(ctx):
    scene = bl.scenes.fan()
    a = ctx.reference(scene, SIZE, samples=16, antialias=True, seed=4)
    b = ctx.reference(scene, SIZE, samples=16, antialias=True, seed=4)
    c = ctx.reference(scene, SIZE, samples=16, antialias=True, seed=5)
    assert a.color.tobytes() == b.color.tobytes()
    assert a.color.tobytes() != c.color.tobytes()
    assert a.antialias and a.positions.shape == (16, 2)


def test_antialias_false_is_the_temporal_reference(ctx):
    scene = bl.scenes.fan()
    default = ctx.reference(scene, SIZE, samples=8)
    explicit = ctx.reference(scene, SIZE, samples=8, antialias=False)
    assert default.color.tobytes() == explicit.color.tobytes()
    assert not explicit.antialias and explicit.positions is None


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"antialias": "yes"}, "antialias must be True or False"),
        ({"antialias": 1}, "antialias must be True or False"),
        ({"antialias": True, "stratified": False}, "temporal reference only"),
        ({"antialias": True, "seed": -1}, "seed"),
    ],
)
def test_bad_antialias_arguments(ctx, kwargs, match):
    with pytest.raises(ValueError, match=match):
        ctx.reference(bl.scenes.fan(), SIZE, samples=4, **kwargs)
