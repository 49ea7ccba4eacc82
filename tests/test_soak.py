"""Soak and load (docs/reliability.md, "Soak"): many evaluations hold memory and GL objects
flat and give the rows of a short run; a 16384 x 16384 request and one that runs out of
memory fail with a clear error and leave the context usable."""

from __future__ import annotations

import gc

import numpy as np
import pytest
from method_picks import pick

import blurlab as bl
from blurlab_bench import soak

SIZE = (32, 18)
HUGE = 16384  # the largest GL_MAX_TEXTURE_SIZE blurlab meets (llvmpipe's, the H100's)
# A plain gather with a tap count, cheap at every size.
GATHER = pick(kind="gather", params=("taps",))


def test_a_soak_holds_memory_and_objects_flat_and_gives_a_short_runs_rows(ctx):
    cycles = 3
    result = soak.soak(ctx, cycles * len(soak.configurations()), SIZE)
    figures = soak.figures(result)
    assert result["same_rows"], (result["first_rows"], result["last_rows"])
    assert len(result["last_rows"]) == len(soak.configurations())
    assert figures["gl_objects_growth"] == 0, result["samples"]
    assert figures["rss_growth_mib"] < 8, result["samples"]
    assert [s["evaluations"] for s in result["samples"]][-1] == figures["evaluations"]
    with pytest.raises(ValueError, match="evaluations must be an integer >= 1"):
        soak.soak(ctx, 0, SIZE)


def test_a_side_by_side_soak_runs_each_device_in_a_process_of_its_own(ctx):
    index = ctx.info()["device_index"]
    index = 0 if index < 0 else index
    evaluations = len(soak.configurations()) + 3
    (result,) = soak.soak_side_by_side([index], evaluations, SIZE, "fan")
    assert result["evaluations"] == evaluations and result["same_rows"]
    assert result["device"].startswith(f"{index}: ")
    assert result["samples"][-1]["evaluations"] == evaluations
    assert soak.device_indices("1, 2,3,3") == [1, 2, 3, 3] and soak.device_indices("") == []
    for bad in ("-1", "gpu", "1,x"):
        with pytest.raises(ValueError, match="EGL device indices separated by commas"):
            soak.device_indices(bad)


def picture(ctx) -> np.ndarray:
    """A small render and blur: what a usable context gives."""
    instant = bl.method_instant(GATHER, {"taps": 4})
    frame = ctx.render(bl.scenes.get("fan"), SIZE, instant=instant)
    return bl.blur(ctx, frame, GATHER, taps=4).color


def test_a_request_beyond_the_texture_limit_names_the_limit(ctx):
    limit = ctx.max_texture_size
    with pytest.raises(ValueError, match=str(limit)):
        ctx.render(bl.scenes.get("fan"), (limit + 1, 16))
    with pytest.raises(ValueError, match=str(limit)):
        ctx.empty((16, limit + 1, 4))


def test_a_16384_square_render_fails_clearly_or_works_and_the_context_stays_usable(ctx):
    before = picture(ctx)
    objects = None
    for _ in range(2):  # a failure leaves nothing behind that a second one adds to
        try:
            frame = ctx.render(bl.scenes.get("fan"), (HUGE, HUGE))
        except bl.GLError as error:  # llvmpipe: a 4 GiB target is over its 1 GiB per texture
            assert "does not fit in the device's memory" in str(error)
            assert "16384x16384" in str(error) and "Use a smaller size" in str(error)
        else:  # a GPU with the memory for it
            assert frame.color.shape == (HUGE, HUGE, 4)
            del frame
        gc.collect()
        assert ctx.gl_errors() == []
        objects = objects or ctx.live_objects()
        assert ctx.live_objects() == objects
    assert np.array_equal(picture(ctx), before)


def test_running_out_of_memory_fails_clearly_and_the_context_stays_usable(ctx):
    """Textures of 4 GiB until the driver refuses one: llvmpipe refuses the first (over its
    1 GiB per texture); a GPU that reports its memory, once it is full."""
    vram = ctx.memory()
    if not ctx.software and not vram:
        pytest.skip("this driver does not report its memory: no bound on what to allocate")
    most = 1 if ctx.software else vram["total"] // (4 * 2**20) + 2
    before = picture(ctx)
    held = []
    refused = None
    try:
        for _ in range(most):
            held.append(ctx.empty((HUGE, HUGE, 4)))
    except bl.GLError as error:
        refused = str(error)
    held.clear()
    gc.collect()
    assert ctx.gl_errors() == []
    assert np.array_equal(picture(ctx), before)
    if refused is None:  # a driver that pages video memory out instead of refusing
        pytest.skip(f"{4 * most} GiB of textures were placed without GL_OUT_OF_MEMORY")
    assert "does not fit in the device's memory" in refused and "16384x16384" in refused


def test_a_sweep_too_large_for_the_device_leaves_no_row(ctx, tmp_path):
    out = tmp_path / "r.csv"
    bl.sweep(ctx, ["fan"], {GATHER: {"taps": [4]}}, SIZE, reference_samples=8, out=out,
             progress=False, repeats=1)  # fmt: skip
    rows = out.read_text()
    if ctx.software:
        with pytest.raises(bl.GLError, match="does not fit"):
            bl.sweep(ctx, ["fan"], {GATHER: {"taps": [4]}}, (HUGE, HUGE),
                     reference_samples=1, out=out, progress=False, repeats=1)  # fmt: skip
        assert out.read_text() == rows  # nothing half-written
    assert ctx.gl_errors() == []
