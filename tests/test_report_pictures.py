"""The study report's pictures made without matplotlib figures: error maps coloured
by a lookup table, crops cut from the arrays, images averaged down for the grid, PNG
compression; and the phases a study times."""

from __future__ import annotations

import concurrent.futures
import importlib
import json
import sys

import matplotlib
import numpy as np
import pytest
from method_picks import pick

import blurlab as bl
from blurlab import metrics
from blurlab.io import images as io
from blurlab.methods import method_instant
from blurlab.studies import gallery, plots

study = importlib.import_module("blurlab.studies.study")
# Two methods whose pictures a report shows (names only, but for the sweep's: a gather with taps).
GATHER = pick(kind="gather", params=("taps",))
OTHER = pick(exclude=(GATHER,))


def test_error_colours_are_matplotlibs_colours_of_the_same_values(rng):
    error = rng.random((90, 160)).astype(np.float32) * 0.3
    vmax = 0.2  # a third of the pixels lie above: they take the brightest colour
    ours = plots.error_colours(error, vmax)
    theirs = matplotlib.colormaps["magma"](
        matplotlib.colors.Normalize(0.0, vmax)(error), bytes=True
    )[..., :3]
    assert ours.shape == (90, 160, 3) and ours.dtype == np.uint8
    same = (ours == theirs).all(axis=-1)
    # Float rounding can put a value on the boundary of two of the 256 bins, no more.
    assert same.mean() > 0.999
    assert (ours[error >= vmax] == theirs[error >= vmax]).all()
    with pytest.raises(ValueError, match="vmax"):
        plots.error_colours(error, 0.0)
    with pytest.raises(ValueError, match="finite"):
        plots.error_colours(np.full((4, 4), np.nan), 1.0)


def test_crops_are_the_pixels_of_each_methods_worst_window():
    reference = np.zeros((90, 160, 4), np.float32)
    reference[..., 3] = 1
    wrong_here = reference.copy()
    wrong_here[60:80, 100:120, :3] = 0.5  # one 20 x 20 error: its window is there
    images = {"reconstruct_a": wrong_here, "b": reference.copy()}
    side = 20
    picture = plots.crops_picture(reference, images, side)
    zoom = -(-plots.CROP_MIN_PIXELS // side)
    cell = side * zoom
    windows = 2  # b has no error: its worst window is the first one, (0, 0)
    assert picture.shape == (
        plots.CROP_HEADER + windows * (cell + plots.CROP_GAP),
        plots.CROP_LABEL_WIDTH + 3 * (cell + plots.CROP_GAP),
        3,
    )
    top, left = plots.CROP_HEADER, plots.CROP_LABEL_WIDTH + (cell + plots.CROP_GAP)
    crop = picture[top : top + cell : zoom, left : left + cell : zoom]
    assert (crop == io.srgb8(wrong_here[60:80, 100:120, :3])).all()
    # The reference's cell of that row is black; the labels are drawn in the margins.
    assert (
        picture[top : top + cell, plots.CROP_LABEL_WIDTH : plots.CROP_LABEL_WIDTH + cell] == 0
    ).all()
    assert (picture[: plots.CROP_HEADER] < 128).any()
    assert (picture[:, : plots.CROP_LABEL_WIDTH] < 128).any()


def test_crop_windows_are_a_quarter_of_the_shorter_side_within_16_to_128_pixels():
    assert plots.crop_side((90, 160, 4)) == 22
    assert plots.crop_side((360, 640)) == 90
    assert plots.crop_side((40, 40, 3)) == 16
    # At 1080p a quarter would be 270: the picture of every window cut from every image.
    assert plots.crop_side((1080, 1920, 4)) == plots.CROP_MAX_SIDE == 128


def test_shrink_averages_whole_blocks():
    array = np.arange(1080 * 1920 * 3, dtype=np.float32).reshape(1080, 1920, 3)
    small = plots.shrink(array, 640)
    assert small.shape == (360, 640, 3)
    assert np.allclose(small[5, 7], array[15:18, 21:24].mean(axis=(0, 1)))
    assert plots.shrink(array[:90, :160], 640) is not None
    assert plots.shrink(array[:90, :160], 640).shape == (90, 160, 3)


def test_png_compression_changes_the_size_not_the_pixels(tmp_path, rng):
    image = rng.random((90, 160, 3)).astype(np.float32)
    image[:45] = 0.25  # something zlib can compress
    fast, small = tmp_path / "fast.png", tmp_path / "small.png"
    io.write(fast, image, png_compression=0)
    io.write(small, image, png_compression=9)
    assert fast.stat().st_size > small.stat().st_size
    assert (io.read(fast) == io.read(small)).all()
    for bad in (10, -1, 2.5, True, "1"):
        with pytest.raises(ValueError, match="png_compression"):
            io.write(tmp_path / "bad.png", image, png_compression=bad)
    assert not list(tmp_path.glob("bad*")) and not list(tmp_path.glob(".bad*"))


def test_write_pictures_writes_every_picture_and_shows_each(tmp_path, rng):
    reference = rng.random((36, 64, 4)).astype(np.float32)
    images = {GATHER: reference * 0.9, OTHER: reference[::-1].copy()}
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        html, encodes = gallery.write_pictures("s", reference, images, tmp_path, pool)
        for encode in encodes:
            encode.result()
    names = ["s_reference", "s_error_scale", "s_crops", "s_images"]
    names += [f"s_{m}{kind}" for m in images for kind in ("", "_error")]
    for name in names:
        assert (tmp_path / f"{name}.png").stat().st_size > 100, name
        if name != "s_images":
            assert f"{name}.png" in html, name
    error = io.read(tmp_path / f"s_{OTHER}_error.png")
    maps = [metrics.error_map(reference, image) for image in images.values()]
    vmax = max(float(np.percentile(np.concatenate([m.ravel() for m in maps]), 99.5)), 1e-3)
    assert plots.error_scale(maps) == vmax  # small maps: every pixel counts
    assert (error[..., :3] == plots.error_colours(maps[1], vmax)).all()


def test_phase_clock_adds_up_and_names_each_phase():
    clock = study.PhaseClock()
    with clock("charts"):
        pass
    clock.add("references", 2.0)
    clock.add("charts", 1.0)
    assert list(clock.seconds) == ["charts", "references"]
    assert 1.0 <= clock.seconds["charts"] < 1.5 and clock.seconds["references"] == 2.0
    assert set(study.PHASES) >= set(clock.seconds)
    json.dumps(clock.seconds)


def test_the_sweep_hands_the_study_what_it_rendered(ctx):
    sweep = importlib.import_module("blurlab.studies.sweep")
    point = {"taps": 5}
    key = (GATHER, json.dumps(point, sort_keys=True))
    caches = {"fan": {"keep_colours": {key}}}
    table = sweep.sweep(
        ctx,
        ["fan"],
        {GATHER: {"taps": [3, 5]}},
        (32, 18),
        reference_samples=4,
        metrics=("psnr",),
        progress=False,
        repeats=1,
        caches=caches,
    )
    cache = caches["fan"]
    assert len(table) == 2 and list(cache["colours"]) == [key]  # taps = 3 was not asked for
    seconds = cache["clock"].seconds
    assert seconds["references"] > 0 and seconds["g_buffers"] > 0
    assert cache["reference"].samples == 4
    frame = cache["frames"][(method_instant(GATHER, point), 1)][0]
    again = bl.blur(ctx, frame, GATHER, **point).color
    assert np.array_equal(cache["colours"][key], again)  # the picture the report would make


def test_image_grid_picture_shows_each_image_and_error_map_named(rng):
    reference = rng.random((90, 160, 4)).astype(np.float32)
    images = {OTHER: reference * 0.5, GATHER: reference.copy()}
    picture = plots.image_grid_picture(reference, images, cell=80)
    label, gap = plots.GRID_LABEL, plots.GRID_GAP
    assert picture.dtype == np.uint8 and picture.shape == (2 * (label + 45 + gap), 3 * 84, 3)
    top = picture[label : label + 45]
    assert np.array_equal(top[:, :80], io.srgb8(plots.shrink(reference[..., :3], 80)))
    assert np.array_equal(top[:, 84:164], io.srgb8(plots.shrink(images[OTHER][..., :3], 80)))
    bottom = picture[2 * label + 45 + gap : 2 * label + 90 + gap]
    same = plots.error_colours(np.zeros((45, 80), np.float32), 0.25)
    assert np.array_equal(bottom[:, 168:248], same)  # the second equals the reference: black
    assert not np.array_equal(bottom[:, 84:164], same)
    assert (picture[:label, :80] < 128).any()  # a name drawn above the reference
    with pytest.raises(ValueError, match="error_scale"):
        plots.image_grid_picture(reference, images, error_scale=0.0)


def test_colour_bar_runs_from_black_to_the_brightest_colour_and_rejects_bad_scales():
    bar = plots.colour_bar(0.05)
    width, height = plots.COLOUR_BAR_SIZE
    assert bar.dtype == np.uint8 and bar.shape[1] > width and bar.shape[0] > height
    row = bar[height // 2]
    inside = row[(row != 255).any(axis=-1)]
    table = plots.error_colours(np.array([[0.0, 0.05]]), 0.05)[0]
    assert np.array_equal(inside[0], table[0]) and np.array_equal(inside[-1], table[1])
    for bad in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="vmax"):
            plots.colour_bar(bad)


def test_error_scale_samples_large_maps_and_keeps_small_ones_whole(rng):
    small = [rng.random((9, 16)).astype(np.float32) for _ in range(3)]
    whole = np.percentile(np.concatenate([m.ravel() for m in small]), 99.5)
    assert plots.error_scale(small) == whole
    large = [rng.random((1080, 1920)).astype(np.float32) for _ in range(2)]
    assert abs(plots.error_scale(large) - 0.995) < 0.002  # uniform errors: the sample agrees
    assert plots.error_scale([np.zeros((4, 4))]) == 1e-3  # floor: a scale of zero draws nothing
    with pytest.raises(ValueError, match="no error values"):
        plots.error_scale([])


def test_charts_draw_in_processes_or_inline_alike(tmp_path):
    import pandas as pd

    table = pd.DataFrame(
        {
            "scene": "s",
            "method": [GATHER, GATHER, OTHER],
            "total_ms": [0.2, 0.4, 0.1],
            "psnr": [30.0, 31.0, 25.0],
            "param_taps": [3, 5, None],
            "clock": "gl_time_elapsed",
            "renderer": "test",
            "width": 160,
            "height": 90,
        }
    )
    for processes in (0, 1):
        with study.chart_pool(processes) as charts:
            work = study.ReportWork(None, charts)
            work.draw(plots.pareto, (table, "s", "psnr"), tmp_path / f"p{processes}.png")
            work.draw(plots.pareto, (table, "nope", "psnr"), tmp_path / "never.png")
            assert work.charts_drawn[0].result() == tmp_path / f"p{processes}.png"
            with pytest.raises(ValueError, match="no rows for scene 'nope'"):
                work.charts_drawn[1].result()  # the drawing's error reaches the study
        assert io.read(tmp_path / f"p{processes}.png").shape[2] >= 3
    assert not (tmp_path / "never.png").exists()
    for bad in (-1, 1.5, True, "2"):
        with pytest.raises(ValueError, match="chart_processes"):
            with study.chart_pool(bad):
                pass


def test_the_per_object_table_takes_the_sweeps_reference_and_gives_the_same_rows(ctx):
    # The study hands textured_spin's reference from its sweep to the per-object table
    # instead of rendering it again: the same rows but for the times.
    objects = importlib.import_module("blurlab.studies.objects")
    from blurlab.core.references import default_reference_samples

    size, scene = (96, 54), bl.scenes.get("textured_spin")
    own = objects.object_errors(ctx, size, renders=(8,))
    samples = default_reference_samples(ctx.render(scene, size))
    reference = ctx.reference(scene, size, samples=samples, progress=False)
    handed = objects.object_errors(ctx, size, renders=(8,), reference=reference)
    same = [c for c in own if not c.startswith("ms_")]
    assert len(own) == 8 and own[same].equals(handed[same])
    with pytest.raises(ValueError, match="the reference is 96x54, the study renders 64x36"):
        objects.object_errors(ctx, (64, 36), renders=(8,), reference=reference)


def test_charts_draw_inline_where_no_interpreter_can_be_started(monkeypatch):
    monkeypatch.setattr(sys, "executable", "")  # an embedded Python has none to start
    with study.chart_pool(2) as charts:
        assert isinstance(charts, study.InlineExecutor)
        assert charts.submit(pow, 2, 5).result() == 32
