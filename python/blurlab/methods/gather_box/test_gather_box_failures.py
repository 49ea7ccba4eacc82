"""gather_box's own failures (docs/failure_cases.md): the box gather against the reconstruction
filter where a silhouette blurs over a still background, and its backward gather's lag on a
turning camera (what every method's failure cases share: tests/test_failure_cases.py)."""

from __future__ import annotations

import numpy as np
from method_picks import EXAMPLE

import blurlab as bl

METHOD = "gather_box"
FILTER = EXAMPLE  # the tile reconstruction filter examples run


def test_silhouette_over_still_background_beats_gather_box(ctx):
    """The thesis's Figure 5.6 as a number: where the teapot's blur covers the still
    background, the reconstruction filter is nearer the reference than the box gather."""
    scene = bl.scenes.teapot_pass()
    size = (96, 54)
    reference = ctx.reference(scene, size, samples=128, progress=False).color
    center, close = ctx.render(scene, size), ctx.render(scene, size, instant="close")
    blurred = np.abs(reference - center.color).max(axis=-1) > 1e-3
    filter_error = np.abs(bl.blur(ctx, center, FILTER).color - reference)
    box_error = np.abs(bl.blur(ctx, close, METHOD).color - reference)
    assert filter_error[blurred].mean() < 0.5 * box_error[blurred].mean()


def test_backward_gather_of_the_closing_frame_lags_a_turning_camera(ctx):
    """docs/failure_cases.md: on a turning camera the G-buffer at t1 gathered backward along
    M (docs/spec.md §4) smears each edge over pixels it never crossed; the same taps mirrored to
    X + s·M are nearer the reference. Recorded as a failure of the specified method."""
    scene = bl.scenes.camera_yaw()
    size = (96, 54)
    reference = ctx.reference(scene, size, samples=128, progress=False).color
    frame = ctx.render(scene, size, instant="close")
    mirrored = bl.Frame(frame.color, frame.depth, -frame.motion, shutter=frame.shutter)
    backward = bl.metrics.psnr(reference, bl.blur(ctx, frame, METHOD).color)
    forward = bl.metrics.psnr(reference, bl.blur(ctx, mirrored, METHOD).color)
    assert forward > backward + 6
