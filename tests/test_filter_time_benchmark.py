"""benchmarks/filter_time.py times what it says: its replayed passes make the method's own image,
every fetch path of its gather reads the same texels, and the reconstruct shader it expands for
moderngl (with or without constants) gives blurlab's bits (on llvmpipe, tiny images)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import blurlab as bl

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import filter_time  # noqa: E402  (a script folder, not a package)

SIZE = (48, 27)


@pytest.fixture(scope="module")
def frame(ctx):
    return ctx.render(bl.scenes.teapot_pass(), SIZE)


@pytest.mark.parametrize(
    ("name", "params"),
    [
        ("reconstruct_mcguire2012", {"k": 4, "samples": 15, "packed_inputs": True}),
        ("reconstruct_guertin2014", {"k": 4}),
        ("gather_coverage", {"film_filter": 0.5}),
    ],
)
def test_replayed_passes_make_the_methods_image(ctx, frame, name, params):
    passes = filter_time.recorded_passes(ctx, frame, name, params)
    steps = [step for step, _ in passes]
    expected = bl.blur(ctx, frame, name, **params).color
    result = passes[-1][1].outputs["result"]
    result.upload(np.zeros(result.shape, np.float32))  # the replay must write it again
    filter_time.replay(passes)
    assert steps[-1] in ("reconstruct", "film")
    np.testing.assert_array_equal(result.download(), expected)


def test_fetch_paths_read_the_same_texels(ctx, frame):
    record = filter_time.fetch_paths(ctx, frame, runs=1)
    variants = record["variants"]
    assert set(variants) == set(filter_time.FETCH_VARIANTS)
    # Only the fetch differs from their kin's: the same texels, the same bits.
    for name in ("one_texture", "buffer_rows", "buffer_blocks", "buffer_rows_no_jitter"):
        assert variants[name]["largest_difference"] == 0.0, name
    # A loop bound the compiler cannot see may round a tap's position otherwise (on the H100,
    # one pixel of the 2.07 million at 1080p changed).
    for name in ("two_textures_runtime_samples", "two_textures_runtime_samples_pcg"):
        assert variants[name]["share_within_1e-3"] >= 0.999, name
    # RGBA16F output: rounding only, within half a unit in the last place of a half float.
    assert 0.0 < variants["two_textures_half_out"]["largest_difference"] < 2e-3
    assert 0.0 < record["tiles_with_taps"] <= 1.0


def test_the_real_pass_through_moderngl_gives_blurlabs_bits(ctx, frame):
    record = filter_time.blurlab_or_moderngl(ctx, frame, runs=1)
    assert record["same_shader_same_bits"]
    assert record["constants_same_bits"] == {label: True for label in filter_time.CONSTANTS}


def test_the_coverage_gather_with_constants_gives_blurlabs_bits(ctx, frame):
    record = filter_time.coverage_gather_constants(ctx, frame, runs=1)
    labels = ["same source", *filter_time.GATHER_CONSTANTS]
    assert {label: record[label]["same_bits"] for label in labels} == dict.fromkeys(labels, True)


def test_barrier_costs_time_every_barrier_on_both_sizes(ctx, frame):
    record = filter_time.barrier_costs(ctx, frame, runs=1)
    assert len(record) == 2 * len(filter_time.BARRIERS)
    assert all(row["back_to_back_ms"] > 0 for row in record.values())


def test_coverage_costs_edit_the_gather_that_blurlab_runs(ctx, frame):
    # The unedited source through moderngl gives blurlab's bits, so the edits' times compare
    # with the real gather's; every edit finds its text (coverage_costs asserts it), and the ones
    # that take out work the image depends on change it.
    record = filter_time.coverage_costs(ctx, frame, runs=1)
    assert record["same source"]["same_bits"]
    assert set(filter_time.COVERAGE_COSTS) | set(filter_time.COVERAGE_CANDIDATES) < set(record)
    assert not record["early exit everywhere (X, its tile, the write)"]["same_bits"]
    assert not record["4 taps a half-shutter"]["same_bits"]
    # The candidates are rewrites that must keep the image, so their times compare like for like.
    assert all(record[label]["same_bits"] for label in filter_time.COVERAGE_CANDIDATES)
    # Half-float colour moves the image by its rounding alone: under a half's step at 1.
    assert 0.0 < record["half inputs: colour RGBA16F"]["largest_change"] < 1e-3
    assert set(filter_time.HALF_INPUTS) < set(record)
