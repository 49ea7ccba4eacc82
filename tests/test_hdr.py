"""HDR content (docs/hdr.md, docs/spec.md §6.2 and §12): emission reaches every method and the
reference unclamped, the HDR scenes, and the HDR metrics against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from method_picks import pick

import blurlab as bl
from blurlab import metrics
from blurlab.studies import failures
from blurlab.studies.study import run_study
from blurlab.studies.sweep import sweep_methods

BRIGHT = 1000.0
SIZE = (160, 90)
# A plain gather with a tap count, for the sweeps, studies and suites below.
GATHER = pick(kind="gather", params=("taps",))


def _facing_quad(width: float, height: float) -> bl.Mesh:
    """A width x height quad in the z = 0 plane, facing +z (the camera)."""
    quad = bl.mesh.plane(width, height)
    turn = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]])  # y -> z
    return quad.transformed(turn)


def lamp_scene(velocity=(0.0, 0.0, 0.0), wall: bool = True) -> bl.Scene:
    """A white emissive quad of BRIGHT (0.02 x 0.02 units: about one pixel at 160 x 90) and
    a larger one, over a lit wall (or black), camera still."""
    scene = bl.Scene(bl.Camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=45), name="lamp")
    scene.background = np.array([0.0, 0.0, 0.0, 1.0])
    if wall:
        scene.add(
            _facing_quad(8.0, 6.0), bl.Material((0.5, 0.4, 0.3)), bl.Motion.static((0, 0, -1.0))
        )
    lamp = bl.Material((0.0, 0.0, 0.0), emission=(1.0, 1.0, 1.0), emission_strength=BRIGHT)
    scene.add(_facing_quad(0.5, 0.5), lamp, bl.Motion.linear((-0.6, 0.1, 0.0), velocity))
    if wall:
        scene.add(_facing_quad(0.02, 0.02), lamp, bl.Motion.static((0.9, -0.3, 0.0)))
    return scene


def _method_backends():
    return [(n, b) for n in bl.methods() for b in bl.method(n).backends]


@pytest.mark.parametrize(("name", "backend"), _method_backends())
def test_a_bright_pixel_passes_every_still_path_unchanged(ctx, name, backend):
    scene = lamp_scene()
    frame = ctx.render(scene, SIZE, instant=bl.method_instant(name, {}))
    color = frame.color
    assert color.max() == BRIGHT  # the G-buffer keeps 1000 exactly: no clamp, no 8-bit target
    assert (color[..., :3] == BRIGHT).all(axis=-1).sum() >= 1
    # Still: exactly 0 on llvmpipe; NVIDIA's per-fragment divide leaves up to half an ulp of
    # the pixel position (7.6e-6 px at 160 px). The test is about the methods' still path.
    assert np.abs(frame.motion).max() < 1e-4
    frame.motion[...] = 0.0
    out = bl.blur(ctx, frame, name, backend).color
    kind = bl.method(name).kind
    if kind in ("filter", "gather", "sequence"):
        # Weighted means of equal taps: float32 rounding only (2 ulp on llvmpipe; 8 allowed).
        np.testing.assert_allclose(out, color, rtol=1e-6, atol=0)
    else:
        # A render method may render at sub-pixel offsets: it antialiases edges even of a still
        # scene, but the inside of the bright quad keeps its value. (One that renders at the
        # pixel centres keeps every pixel: its folder tests that.)
        assert kind == "render"
        inside = (color[..., 0] == BRIGHT) & (
            np.abs(np.diff(color[..., 0], axis=1, prepend=0)) == 0
        )
        inside &= np.roll(color[..., 0], 1, 0) == BRIGHT
        inside &= np.roll(color[..., 0], -1, 0) == BRIGHT
        inside &= np.roll(color[..., 0], -1, 1) == BRIGHT
        assert inside.sum() > 20
        np.testing.assert_allclose(out[inside], color[inside], rtol=1e-5)


# Post-process methods, which read the frame's arrays (and the camera's transforms, which the
# frame below takes from a still render); the render methods need the scene: the rendered test
# above covers them.
ARRAY_METHODS = [n for n in bl.methods() if bl.method(n).kind != "render"]


@pytest.mark.parametrize("name", ARRAY_METHODS)
def test_a_1000x_pixel_in_an_array_frame_comes_back_unchanged(ctx, rng, name):
    color = rng.random((48, 64, 4), dtype=np.float32)
    color[20, 30, :3] = BRIGHT
    still_camera = ctx.render(lamp_scene(), (64, 48)).camera
    depth, motion = np.full((48, 64), 5.0, np.float32), np.zeros((48, 64, 2), np.float32)
    frame = bl.Frame(color, depth, motion, camera=still_camera)
    out = bl.blur(ctx, frame, name).color
    np.testing.assert_allclose(out, color, rtol=1e-6, atol=0)
    assert out[20, 30, :3] == pytest.approx(BRIGHT, rel=1e-6)


def test_the_reference_conserves_radiance_under_pure_translation(ctx):
    """A BRIGHT quad crossing a black image along x: the reference's total radiance is the mean
    of its sub-frames' totals, and within their sampling error of the exact radiance. Each
    sub-frame covers a whole number of columns (pixel centres); averaged over the shutter the
    covered width becomes the quad's exact width in pixels."""
    scene = lamp_scene(velocity=(60.0, 0.0, 0.0), wall=False)
    ref = ctx.reference(scene, SIZE, samples=64, progress=False)
    total = float(ref.color[..., :3].sum(dtype=np.float64))
    renders = [ctx.render(scene, SIZE, instant=float(t)).color for t in ref.times]
    subframes = [float(c[..., :3].sum(dtype=np.float64)) for c in renders]
    assert total == pytest.approx(np.mean(subframes), rel=1e-5)
    # Rows: the vertical extent does not move, so its pixel-centre count is the same in every
    # sub-frame. Width: 0.5 units at distance 4, fov 45 over 90 rows.
    rows = int((renders[0][..., 0] > 0).any(axis=1).sum())
    assert all(int((c[..., 0] > 0).any(axis=1).sum()) == rows for c in renders)
    width = 0.5 * (SIZE[1] / 2) / (4.0 * math.tan(math.radians(22.5)))
    exact = rows * width * 3 * BRIGHT
    worst = max(abs(s / exact - 1) for s in subframes)
    assert worst > 0.02  # one sub-frame gains or misses a whole column: 1 / 13.6 of the width
    assert abs(total / exact - 1) < 0.005  # the mean of 64 stratified ones does not


@pytest.mark.parametrize("name", ["night_street", "sparks", "spinning_ring", "neon_pan"])
def test_hdr_flip_of_identical_images_is_zero(ctx, name):
    image = ctx.render(bl.scenes.get(name), SIZE).color
    assert image.max() > 100
    assert metrics.hdr_flip(image, image) == 0.0


def test_tone_mapper_against_hand_computed_values():
    # Reinhard x / (1 + x) on exposure · rgb, then sRGB: 1 -> 0.5 -> 0.73536, 3 -> 0.75 -> 0.88083
    ones = np.ones((2, 2, 3))
    assert metrics.tone_map(ones, 1.0) == pytest.approx(np.full((2, 2, 3), 0.7353569830524495))
    assert metrics.tone_map(ones, 3.0) == pytest.approx(np.full((2, 2, 3), 0.8808250210902997))
    assert metrics.tone_map(-ones, 1.0) == pytest.approx(np.zeros((2, 2, 3)))  # negatives: 0
    bright = metrics.tone_map(np.array([[[100.0, 1000.0, 1e4]]]), 1.0)[0, 0]
    assert (np.diff(bright) > 0).all() and (bright < 1).all()  # highlights stay apart
    with pytest.raises(ValueError, match="exposure"):
        metrics.tone_map(ones, 0.0)


def test_exposure_against_hand_computed_values():
    # Reinhard's key: 0.18 / exp(mean log(1e-4 + Y)).
    grey = np.full((4, 4, 3), 0.18)
    assert metrics.exposure(grey) == pytest.approx(0.18 / (0.18 + 1e-4))
    half = np.zeros((4, 4, 3))
    half[:2] = 1.0
    assert metrics.exposure(half) == pytest.approx(0.18 / math.sqrt(1e-4 * (1 + 1e-4)))


def test_tone_mapped_psnr_and_ssim_against_hand_computed_values():
    a, b = np.ones((16, 16, 3)), np.full((16, 16, 3), 3.0)
    # Uniform images: tone-mapped 0.73536 and 0.88083 at exposure 1.
    assert metrics.psnr_tm(a, b, exposure=1.0) == pytest.approx(16.74464837117299)
    # SSIM of two constants: (2 μa μb + C1) / (μa² + μb² + C1), the variance terms being 1.
    assert metrics.ssim_tm(a, b, exposure=1.0) == pytest.approx(0.9839288310625312)
    assert metrics.psnr_tm(a, a) == math.inf
    assert metrics.ssim_tm(b, b) == pytest.approx(1.0)


def test_log_luminance_error_and_energy_ratio_against_hand_computed_values():
    a, b = np.ones((8, 8, 3)), np.full((8, 8, 3), 2.0)
    # |log2((1e-4 + 2) / (1e-4 + 1))|: one stop, less the δ
    assert metrics.log_luminance_error(a, b) == pytest.approx(math.log2(2.0001 / 1.0001))
    assert metrics.log_luminance_error(a, a) == 0.0
    c = a.copy()
    c[:4] = 3.0
    assert metrics.energy_ratio(a, c) == pytest.approx(2.0)
    black = np.zeros((8, 8, 3))
    assert metrics.energy_ratio(black, black) == 1.0
    assert metrics.energy_ratio(black, a) == math.inf


def test_hdr_flip_exposure_range_is_flips_own_from_the_reference(ctx):
    import flip_evaluator

    image = ctx.reference(bl.scenes.get("sparks"), SIZE, samples=64, progress=False).color
    start, stop = metrics.flip_exposure_range(image)
    rgb = np.ascontiguousarray(image[..., :3])
    _, _, used = flip_evaluator.evaluate(rgb, rgb, "HDR", inputsRGB=False, applyMagma=False)
    assert start == pytest.approx(used["startExposure"], abs=1e-4)
    assert stop == pytest.approx(used["stopExposure"], abs=1e-4)
    assert stop - start > 10  # a range of more than ten stops: the sparks reach 10^4


def test_a_lost_highlight_is_invisible_to_clipped_psnr_but_not_to_the_hdr_metrics():
    reference = np.full((32, 32, 3), 0.05)
    reference[16, 16] = 100.0
    lost = reference.copy()
    lost[16, 16] = 1.0  # the highlight clipped to 1
    assert metrics.psnr(reference, lost) == math.inf  # LDR metrics clip to [0, 1]: no error
    assert metrics.psnr_tm(reference, lost) < 60
    assert metrics.hdr_flip(reference, lost) > 0
    assert metrics.log_luminance_error(reference, lost) > 0
    assert metrics.energy_ratio(reference, lost) < 0.9


def test_hdr_metrics_refuse_non_finite_images():
    image = np.ones((8, 8, 3))
    bad = image.copy()
    bad[0, 0, 0] = np.nan
    for metric in metrics.HDR_METRICS.values():
        with pytest.raises(ValueError, match="NaN or inf"):
            metric(image, bad)


def test_emission_is_validated():
    with pytest.raises(ValueError, match="emission_strength"):
        bl.Material(emission=(1, 1, 1), emission_strength=2e4)
    with pytest.raises(ValueError, match="emission_strength"):
        bl.Material(emission=(1, 1, 1), emission_strength=-1.0)
    with pytest.raises(ValueError, match="colour in"):
        bl.Material(emission=(2, 1, 1), emission_strength=10.0)
    with pytest.raises(TypeError, match="emission_strength"):
        bl.Material(emission_strength="bright")
    material = bl.Material(emission=(1.0, 0.5, 0.0), emission_strength=1e4)
    assert material.radiance.tolist() == [1e4, 5e3, 0.0]


def test_hdr_scenes_are_tagged_and_bright(ctx):
    assert bl.scenes.names("hdr") == ["night_street", "sparks", "spinning_ring", "neon_pan"]
    assert not set(bl.scenes.names("hdr")) & set(bl.scenes.names())  # the default list is LDR
    assert not any(bl.scenes.get(n).hdr for n in bl.scenes.names())
    with pytest.raises(ValueError, match="hdr"):
        bl.scenes.names("bright")
    moving_camera = []
    for name in bl.scenes.names("hdr"):
        scene = bl.scenes.get(name)
        assert scene.hdr and bl.scenes.describe(name)
        frame = ctx.render(scene, SIZE)
        assert frame.color.max() > 100 and np.isfinite(frame.color).all()
        assert np.abs(frame.motion).max() > 4  # the lights streak by pixels, even at 160 x 90
        if scene.camera.motion is not None:
            moving_camera.append(name)
    assert moving_camera == ["neon_pan"]


def test_energy_ratio_of_every_method_on_every_hdr_scene_is_finite_and_reported(ctx):
    methods = sweep_methods()
    table = bl.sweep(
        ctx,
        bl.scenes.names("hdr"),
        {name: {} for name in methods},  # each method once, at its defaults
        size=SIZE,
        metrics=("energy_ratio",),
        repeats=1,
        progress=False,
    )
    assert len(table) == len(methods) * len(bl.scenes.names("hdr"))
    assert np.isfinite(table["energy_ratio"]).all()
    assert (table["energy_ratio"] > 0).all()
    print(table.pivot(index="method", columns="scene", values="energy_ratio").round(3))


def test_sweeps_add_the_hdr_metrics_on_hdr_scenes_only(ctx):
    table = bl.sweep(
        ctx, ["spinning_ring", "fan"], {GATHER: {}}, size=SIZE, repeats=1, progress=False
    )
    ring, fan = table[table["scene"] == "spinning_ring"], table[table["scene"] == "fan"]
    for name in ("hdr_flip", "psnr_tm", "ssim_tm", "log_lum_error", "energy_ratio", "exposure"):
        assert np.isfinite(ring[name]).all()
        assert fan[name].isna().all()
    assert np.isfinite(fan["flip"]).all() and np.isfinite(ring["flip"]).all()
    with pytest.raises(ValueError, match="unknown metrics"):
        bl.sweep(ctx, ["fan"], {GATHER: {}}, size=SIZE, metrics=("hdr_flop",))


def test_study_report_shows_hdr_scenes_tone_mapped_with_the_exposure(ctx, tmp_path):
    report = run_study(
        ctx,
        ["spinning_ring"],
        SIZE,
        tmp_path,
        reference_samples=16,
        grids={GATHER: {"taps": [5]}},
        progress=False,
    )
    text = report.read_text()
    table = pd.read_csv(tmp_path / "results.csv")
    exposure = float(table["exposure"].iloc[0])
    assert "HDR scene" in text and f"{exposure:.4g}" in text and "PSNR_TM" in text
    assert (tmp_path / "spinning_ring_reference.png").is_file()
    # The comparator's panels hold the linear colour, tone-mapped in the page about the same
    # exposure (tests/test_comparator_browser.py drives the exposure control).
    assert (tmp_path / "look" / "spinning_ring.js").is_file()
    assert f"about {exposure:.4g} (Reinhard)" in text


def test_hdr_scores_names_its_metrics_and_the_exposure():
    a, b = np.ones((8, 8, 3)), np.full((8, 8, 3), 2.0)
    scores = metrics.hdr_scores(a, b, ("energy_ratio",))
    assert scores == {"energy_ratio": pytest.approx(2.0), "exposure": metrics.exposure(a)}
    with pytest.raises(ValueError, match="unknown HDR metrics"):
        metrics.hdr_scores(a, b, ("psnr",))


def test_the_failure_suite_measures_hdr_scenes_with_the_hdr_metrics(ctx):
    table = failures.evaluate(ctx, ["spinning_ring"], [GATHER], SIZE, 2, 16, False)
    assert np.isfinite(table[["hdr_flip", "psnr_tm", "energy_ratio", "exposure"]].to_numpy()).all()


def test_a_sweep_takes_hdr_flips_exposure_range_once_per_reference(ctx, monkeypatch):
    """HDR-FLIP runs on the GPU in sweeps; its exposure range (a median over the reference's
    pixels) is made once per reference, not once per evaluation."""
    made = []
    exposure_range = metrics.hdr.flip_exposure_range

    def counted(reference):
        made.append(reference.shape)
        return exposure_range(reference)

    monkeypatch.setattr(metrics.hdr, "flip_exposure_range", counted)
    exposed = []  # the rows' exposure (a log-average over the reference): once per reference too
    exposure = metrics.exposure
    monkeypatch.setattr(metrics, "exposure", lambda image: exposed.append(1) or exposure(image))
    grid = {GATHER: {"taps": [4, 8, 16]}}
    table = bl.sweep(
        ctx, ["spinning_ring"], grid, SIZE, reference_samples=16, metrics=("hdr_flip",)
    )
    assert len(table) == 3 and len(made) == 1
    assert len(exposed) == 1 and table["exposure"].nunique() == 1
    with pytest.raises(TypeError, match="gpu_arguments is a callable, given with gpu"):
        metrics.Metric(
            name="x",
            doc="d",
            spec="§6",
            higher_is_better=True,
            range=(0, 1),
            numpy=abs,
            label="x",
            gpu_arguments=lambda reference: {},
        )
