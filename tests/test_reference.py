"""The converged reference (docs/spec.md §1): N renders across the shutter, averaged on the GPU."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.core.references import sample_times  # the twin's, which the reference uses
from blurlab.twins import projection

SIZE = (160, 90)


def test_one_sample_equals_a_render_at_its_time(ctx):
    scene = bl.scenes.teapot_pass()
    reference = ctx.reference(scene, SIZE, (0.0, 0.02), samples=1, stratified=False)
    np.testing.assert_array_equal(reference.times, [0.01])
    frame = ctx.render(scene, SIZE, (0.0, 0.02), instant=0.01)
    assert reference.color.tobytes() == frame.color.tobytes()


def test_stratified_times_stay_in_their_strata():
    times = sample_times((1.0, 2.0), 16, True, seed=5)
    strata = np.floor((times - 1.0) * 16)
    np.testing.assert_array_equal(strata, np.arange(16))
    assert not np.allclose(times - 1.0 - (np.arange(16) + 0.5) / 16, 0)


def test_still_scene_equals_one_render_for_any_n(ctx):
    scene = bl.scenes.teapot_pass()
    scene.objects[-1].motion = bl.Motion.static((-0.2, 0.0, 0.6))
    one = ctx.render(scene, SIZE).color
    for n in (2, 7, 32):
        np.testing.assert_allclose(
            ctx.reference(scene, SIZE, samples=n).color, one, rtol=0, atol=1e-6
        )


def square_scene(distance_px: float):
    """A flat white square moving right across a black background, parallel to the image."""
    camera = bl.Camera((0.0, 0.0, 5.0), (0.0, 0.0, 0.0), fov_y=40)
    scene = bl.Scene(
        camera,
        light=bl.DirectionalLight(color=(0, 0, 0), ambient=(1, 1, 1)),
        background=(0, 0, 0, 1),
        shutter=(0.0, 1.0),
    )
    units_per_px = 2 * 5.0 * np.tan(np.radians(20)) / SIZE[1]
    square = bl.mesh.plane(1.0, 1.0).transformed(
        np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]])
    )  # faces +z
    scene.add(
        square,
        bl.Material((1, 1, 1)),
        bl.Motion.linear((-1.0, 0.0, 0.0), (distance_px * units_per_px, 0.0, 0.0)),
    )
    return scene


def analytic_coverage(scene, row: float) -> np.ndarray:
    """Fraction of the shutter during which each pixel center of `row` lies in the square."""
    camera = scene.camera
    corners = np.array([[-0.5, -0.5, 0.0], [0.5, 0.5, 0.0]])
    edges = [
        projection.project(corners + scene.objects[0].model(t)[:3, 3], camera, t, SIZE)[0]
        for t in (0.0, 1.0)
    ]
    (l0, r0), (l1, r1) = (e[:, 0] for e in edges)
    x = np.arange(SIZE[0]) + 0.5
    s = np.linspace(0, 1, 200001)[:, None]  # dense in time: exact to 5e-6
    inside = (l0 + (l1 - l0) * s <= x) & (x < r0 + (r1 - r0) * s)
    return inside.mean(axis=0)


@pytest.mark.parametrize("samples", [8, 40])
def test_translating_square_has_the_box_filtered_profile(ctx, samples):
    scene = square_scene(distance_px=30.0)
    reference = ctx.reference(scene, SIZE, samples=samples, stratified=False)
    row = SIZE[1] // 2
    expected = analytic_coverage(scene, row)
    measured = reference.color[row, :, 0]
    assert np.abs(measured - expected).max() <= 1 / samples + 1e-3
    assert ((expected > 0.1) & (expected < 0.9)).sum() >= 20  # a real ramp, not a step


def test_samples_needed_covers_the_longest_motion(ctx):
    frame = ctx.render(square_scene(distance_px=30.0), SIZE)
    assert bl.reference_samples_needed(frame) == int(
        np.ceil(np.linalg.norm(frame.motion, axis=-1).max())
    )
    assert 29 <= bl.reference_samples_needed(frame) <= 31


@pytest.mark.parametrize("samples", [0, -3, 2.5, True])
def test_bad_sample_counts(ctx, samples):
    with pytest.raises(ValueError, match="samples N must be an integer in 1"):
        ctx.reference(bl.scenes.fan(), SIZE, samples=samples)


def test_a_detached_reference_travels_to_another_process_and_back_bit_for_bit(ctx):
    """Reference.detached/attached: how a cluster worker hands its reference to a helper."""
    import pickle

    reference = ctx.reference(bl.scenes.get("fan"), (32, 18), samples=4)
    detached = pickle.loads(pickle.dumps(reference.detached()))
    assert detached.texture is None
    attached = detached.attached(ctx)
    np.testing.assert_array_equal(attached.texture.download(), reference.texture.download())
    assert (attached.samples, attached.seed, attached.antialias) == (4, reference.seed, False)
    np.testing.assert_array_equal(attached.times, reference.times)
    with pytest.raises(ValueError, match="detached reference's image"):
        reference.attached(ctx)
