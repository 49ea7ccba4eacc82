"""Tile lists and indirect dispatch (docs/spec.md §9.3, blurlab.methods.tiles): the classify pass
sorts tiles into lists as its twin classes them, with the counters as indirect-dispatch counts,
and a pass dispatched over each class's list gives the same bits as a full dispatch in which
every tile runs its class's function."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

from blurlab.methods import tiles
from blurlab.methods.passes import Pass

TILE = 16  # tests/shaders/tile_class_blur.comp's work group


def _three_class_motion(rng, width, height):
    """Still on the left, a uniform 6 px motion in the middle, random motion on the right."""
    frame = random_frame(rng, width, height)
    motion = frame.motion
    motion[:, : width // 3] = 0.0
    motion[:, width // 3 : 2 * width // 3] = [6.0, 0.0]
    return frame.color, motion


@pytest.mark.parametrize("size", [(160, 90), (97, 61)])
def test_classes_and_lists_match_the_twin(ctx, rng, size):
    color, motion = _three_class_motion(rng, *size)
    lists = tiles.classify_motion(ctx, {}, ctx.upload(motion), TILE)
    classes = lists.classes.download()[..., 0]
    expected = tiles.motion_classes(motion, TILE)
    np.testing.assert_array_equal(classes, expected)
    assert set(np.unique(expected)) == {0, 1, 2}
    counts = lists.counts.download()[0, :, 0].reshape(-1, 4)
    np.testing.assert_array_equal(counts[:, 0], np.bincount(expected.ravel(), minlength=3))
    np.testing.assert_array_equal(counts[:, 1:3], 1)  # the indirect dispatch's y and z
    entries = lists.lists.download()[..., 0]
    for cls in range(3):  # each list holds its class's tiles, in whatever order
        listed = np.sort(entries[cls, : counts[cls, 0]])
        np.testing.assert_array_equal(listed, np.flatnonzero(expected.ravel() == cls))


@pytest.mark.parametrize("size", [(160, 90), (97, 61), (16, 16)])
def test_a_pass_over_each_list_gives_the_bits_of_a_full_dispatch(ctx, rng, test_shader, size):
    color, motion = _three_class_motion(rng, *size)
    inputs = {"color": ctx.upload(color), "motion": ctx.upload(motion)}
    lists = tiles.classify_motion(ctx, {}, inputs["motion"], TILE)
    inputs["tile_class_in"] = lists.classes
    shader = str(test_shader("tile_class_blur.comp"))
    full = ctx.empty(color.shape)
    ctx.shader_pass(shader).run(inputs, {"result": full})
    listed = ctx.empty(color.shape)
    timings = {}
    step = Pass("class_blur", shader)
    for cls in range(len(lists.names)):
        tiles.run_over_list(
            ctx, timings, step, lists, cls, inputs, {"result": listed}, defines={"OVER_LIST": 1}
        )
    assert listed.download().tobytes() == full.download().tobytes()
    assert list(timings) == ["class_blur[still]", "class_blur[uniform]", "class_blur[mixed]"]
    assert ctx.gl_errors() == []


def test_an_empty_list_dispatches_nothing(ctx, test_shader):
    motion = np.zeros((40, 50, 2), np.float32)  # every tile still
    color = np.random.default_rng(3).random((40, 50, 4), dtype=np.float32)
    inputs = {"color": ctx.upload(color), "motion": ctx.upload(motion)}
    lists = tiles.classify_motion(ctx, {}, inputs["motion"], TILE)
    inputs["tile_class_in"] = lists.classes
    out = ctx.empty(color.shape)
    step = Pass("class_blur", str(test_shader("tile_class_blur.comp")))
    for cls in (1, 2):  # no tile in these lists: the output keeps its zeros
        tiles.run_over_list(
            ctx, {}, step, lists, cls, inputs, {"result": out}, defines={"OVER_LIST": 1}
        )
    assert not out.download().any()
    tiles.run_over_list(ctx, {}, step, lists, 0, inputs, {"result": out}, defines={"OVER_LIST": 1})
    np.testing.assert_array_equal(out.download(), color)


def test_bad_lists_and_classes_are_refused(ctx, test_shader):
    with pytest.raises(ValueError, match="tile"):
        tiles.empty_lists(ctx, (90, 160), 0, tiles.MOTION_CLASSES)
    lists = tiles.empty_lists(ctx, (32, 32), TILE, tiles.MOTION_CLASSES)
    step = Pass("class_blur", str(test_shader("tile_class_blur.comp")))
    with pytest.raises(ValueError, match="outside 0..2"):
        tiles.run_over_list(ctx, {}, step, lists, 3, {}, {})
    shader = ctx.shader_pass(str(test_shader("tile_class_blur.comp")), {"OVER_LIST": 1})
    counts = ctx.empty((1, 6, 1), "uint32")  # not 4 texels per list
    image = ctx.empty((32, 32, 4))
    textures = {"color": image, "motion": ctx.empty((32, 32, 2)), "tile_class_in": lists.classes}
    with pytest.raises(ValueError, match="4 texels per list"):
        shader.native.run_indirect(
            {k: t.native for k, t in {**textures, "tile_lists": lists.lists}.items()},
            {"result": image.native},
            {"tile_class": 0},
            counts.native,
            0,
        )
