"""stochastic (docs/spec.md §4, the OGRE paper; spec.md here): K jittered time slices combined per
pixel."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.core.render import render_targets
from blurlab.methods.stochastic import twin

SIZE = (96, 54)


@pytest.mark.parametrize("slices", [3, 4])
def test_combination_matches_reference(ctx, slices):
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, SIZE)
    renders = np.zeros((slices, 4, SIZE[1], SIZE[0], 4))
    for index, t in enumerate(twin.slice_times(frame.shutter, slices, 9)):
        for position, p in enumerate(twin.ROTATED_GRID):
            targets, _, _ = render_targets(
                ctx, scene, SIZE, frame.shutter, float(t), 0, (0.5 - p[0], 0.5 - p[1])
            )
            renders[index, position] = targets["color"].download()
    result = bl.blur(ctx, frame, "stochastic", slices=slices, seed=9)
    np.testing.assert_allclose(result.color, twin.combine(renders, slices, 9), atol=1e-6)


def test_error_against_the_reference_falls_as_k_grows(ctx):
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, SIZE)
    reference = ctx.reference(scene, SIZE, samples=512, progress=False).color
    errors = [
        np.sqrt(np.mean((bl.blur(ctx, frame, "stochastic", slices=k).color - reference) ** 2))
        for k in (1, 2, 4, 8)
    ]
    assert all(b < a for a, b in zip(errors, errors[1:], strict=False)), errors


def test_weights_sum_to_one(ctx):
    scene = bl.Scene(
        light=bl.DirectionalLight(color=(0, 0, 0), ambient=(1, 1, 1)),
        background=(0.25, 0.5, 0.75, 1.0),
    )
    scene.add(bl.mesh.sphere(), bl.Material((0.25, 0.5, 0.75)))
    result = bl.blur(ctx, ctx.render(scene, SIZE), "stochastic", slices=5)
    np.testing.assert_allclose(
        result.color, np.float32([0.25, 0.5, 0.75, 1.0]) + 0 * result.color, atol=1e-6
    )


def test_every_slice_is_used_and_choices_are_deterministic():
    y, x = np.mgrid[0:64, 0:64]
    chosen = twin.slice_of(x, y, 2, 7, 3)
    assert set(np.unique(chosen)) == set(range(7))
    np.testing.assert_array_equal(chosen, twin.slice_of(x, y, 2, 7, 3))
    quarters = [twin.slice_of(x, y, i, 4, 3) for i in range(4)]
    assert (np.sort(np.stack(quarters), axis=0) == np.arange(4)[:, None, None]).all()


@pytest.mark.parametrize("slices", [0, 65])
def test_bad_slice_counts(ctx, slices):
    with pytest.raises(ValueError, match=r"slices = .* is outside 1\.\.64"):
        bl.blur(ctx, ctx.render(bl.scenes.fan(), (16, 16)), "stochastic", slices=slices)
