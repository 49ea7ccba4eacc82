"""blurlab.blender: a blurlab Scene rendered by Blender in a child process (docs/crosscheck.md).
Tiny images and few samples: CI runs these on llvmpipe and Cycles on the CPU."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from method_picks import pick
from test_reference import square_scene

import blurlab as bl
from blurlab.blender import crosscheck, environment
from blurlab.studies.peers import EEVEE_ROWS, check_peers
from blurlab.studies.study import run_study

SIZE = (80, 45)
needs_bpy = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not set up (blurlab blender install)"
)


def leftovers() -> set:
    return {p.name for p in Path(tempfile.gettempdir()).glob("blurlab blender *")}


def fake_python(folder: Path, body: str) -> Path:
    """An 'interpreter' at a path with spaces that runs `body` as a shell script."""
    path = folder / "a python with spaces"
    path.write_text("#!/bin/sh\n" + body + "\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def mask_stats(coverage: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixels more than half covered, and the coverage-weighted centroid (x, y)."""
    y, x = np.indices(coverage.shape)
    total = coverage.sum()
    return coverage > 0.5, np.array([(coverage * x).sum(), (coverage * y).sum()]) / total


@needs_bpy
def test_cycles_converges_to_the_antialiased_reference(ctx):
    scene = square_scene(distance_px=30.0 * SIZE[1] / 90)
    cycles = bl.blender.render(scene, SIZE, engine="CYCLES", samples=256, seed=1)
    assert cycles.color.shape == (*SIZE[::-1], 4) and cycles.color.dtype == np.float32
    assert cycles.settings["pixel_filter_type"] == "BOX" and cycles.settings["max_bounces"] == 0
    assert cycles.wall_s >= cycles.render_s > 0 and "Cycles" in cycles.device
    antialiased = ctx.reference(scene, SIZE, samples=256, antialias=True).color
    temporal = ctx.reference(scene, SIZE, samples=256).color
    aa, plain = bl.metrics.psnr(antialiased, cycles.color), bl.metrics.psnr(temporal, cycles.color)
    assert aa > 42  # Cycles' own noise at 256 spp limits it
    assert aa > plain + 5  # pixel centers alias the still edges


@needs_bpy
@pytest.mark.parametrize("instant", [0.0, 1.0])
def test_geometry_at_an_instant_matches(ctx, instant):
    scene = square_scene(distance_px=30.0 * SIZE[1] / 90)
    cycles = bl.blender.render(scene, SIZE, samples=64, instant=instant).color[..., 0]
    ours = ctx.reference(scene, SIZE, (instant, instant), samples=64, antialias=True).color
    (mask_c, centroid_c), (mask_b, centroid_b) = mask_stats(cycles), mask_stats(ours[..., 0])
    assert (mask_c & mask_b).sum() / (mask_c | mask_b).sum() >= 0.99
    assert np.abs(centroid_c - centroid_b).max() < 0.1


@needs_bpy
def test_lambert_and_a_moving_camera_match(ctx):
    camera = bl.Camera(
        (0, 0.5, 4.0),
        (0, 0, 0),
        fov_y=45,
        motion=bl.Motion.linear(velocity=(1.0, 0, 0), spin_axis=(0, 1, 0), spin_rate=0.3),
    )
    light = bl.DirectionalLight((0.4, 1.0, 0.6), (0.8, 0.8, 0.8), (0.2, 0.2, 0.2))
    scene = bl.Scene(camera, light, background=(0.1, 0.1, 0.2, 1), shutter=(0, 0.5))
    spin = bl.Motion.linear(spin_axis=(0, 1, 0), spin_rate=4.0)
    scene.add(bl.mesh.sphere(0.7), bl.Material((0.9, 0.5, 0.2)), spin)
    cycles = bl.blender.render(scene, SIZE, samples=128).color
    antialiased = ctx.reference(scene, SIZE, samples=256, antialias=True).color
    assert bl.metrics.psnr(antialiased, cycles) > 38


def interior(object_id: np.ndarray, count: int) -> np.ndarray:
    """Pixels whose 3x3 neighbourhood is all one object: no pass value there mixes surfaces."""
    h, w = object_id.shape
    padded = np.pad(object_id, 1, constant_values=-2)
    same = np.ones((h, w), bool)
    for dy in range(3):
        for dx in range(3):
            same &= padded[dy : dy + h, dx : dx + w] == object_id
    return same & (object_id >= 0) & (object_id < count)


def test_cycles_shutter_is_the_span_its_time_table_reaches():
    n = bl.blender.CYCLES_SHUTTER_TABLE
    start, end = bl.blender.cycles_shutter((0.0, 1.0))
    assert start == pytest.approx(255 / 2 / 256**2) and n == 256
    assert end - start == pytest.approx((255 / 256) ** 2)
    t0, t1 = bl.blender.cycles_shutter((0.2, 0.7))
    assert (t0, t1) == pytest.approx((0.2 + 0.5 * start, 0.2 + 0.5 * end))
    with pytest.raises(ValueError, match="shutter"):
        bl.blender.cycles_shutter((1.0, 0.0))


@needs_bpy
def test_cycles_blurs_over_the_span_cycles_shutter_gives(ctx):
    """The occluder's bar moves 42 px: over the nominal shutter blurlab's blurred centroid
    sits 0.1 px off Cycles' (0.2 % of the shutter early: 0.08 px of it); over cycles_shutter
    it is within 0.05 px."""
    scene = crosscheck.mask_scene(crosscheck.occluder_scene(), "bar")
    size = (160, 90)
    cycles = bl.blender.render(scene, size, samples=64, seed=0)
    assert cycles.settings["shutter_spanned"] == pytest.approx(
        bl.blender.cycles_shutter(scene.shutter)
    )
    theirs = mask_stats(cycles.color[..., 0])[1]
    shift = {}
    for label, shutter in (("nominal", None), ("spanned", cycles.settings["shutter_spanned"])):
        ours = ctx.reference(scene, size, shutter, samples=256, antialias=True).color[..., 0]
        shift[label] = abs(mask_stats(ours)[1][0] - theirs[0])
    assert shift["spanned"] < 0.05 < shift["nominal"] - shift["spanned"], shift


@needs_bpy
def test_blenders_vector_and_depth_passes_match_the_gbuffer(ctx, tmp_path):
    """Blender's own Vector and Depth passes, imported with the "blender" convention, give
    blurlab's G-buffer: a box translating across the view and one spinning slowly (so both
    half-frames move alike), instant at the shutter's centre, which is Blender's frame."""
    size = (160, 90)
    camera = bl.Camera((0, 1.8, 5.0), (0, 0, 0), fov_y=40)
    light = bl.DirectionalLight((0.4, 1.0, 0.6), (0.8, 0.8, 0.8), (0.2, 0.2, 0.2))
    scene = bl.Scene(camera, light, background=(0.1, 0.1, 0.2, 1), shutter=(0.0, 0.2))
    scene.add(
        bl.mesh.box((1.0, 1.0, 1.0)),
        bl.Material((0.9, 0.5, 0.2)),
        bl.Motion.linear(start=(-1.4, 0, 0.3), velocity=(5.0, 0, 0)),
    )
    scene.add(
        bl.mesh.box((1.2, 0.8, 1.0)),
        bl.Material((0.2, 0.6, 0.9)),
        bl.Motion.linear(start=(1.3, 0.1, 0), spin_axis=(0.3, 1.0, 0.2), spin_rate=0.8),
    )
    path = tmp_path / "passes.exr"
    blender = bl.blender.render(scene, size, passes=path)
    assert blender.settings["instant"] == pytest.approx(0.1) and blender.settings["samples"] == 1
    assert not blender.settings["use_motion_blur"]
    imported = bl.Frame.from_exr(path, convention="blender", shutter_fraction=1.0)
    ours = ctx.render(scene, size)  # instant "center" = 0.1, motion over the shutter
    assert imported.color.shape == ours.color.shape
    inside = interior(ours.object_id, len(scene.objects))
    for i in range(len(scene.objects)):
        assert (inside & (ours.object_id == i)).sum() >= 400  # both boxes are compared
    motion_error = np.abs(imported.motion - ours.motion)[inside].max()
    depth_error = np.abs(imported.depth / ours.depth - 1)[inside].max()
    print(f"Blender passes vs G-buffer: {motion_error:.4f} px, {depth_error:.2e} relative depth")
    assert np.abs(ours.motion[inside]).max() > 20  # the translation is seen
    assert motion_error < 0.05
    assert depth_error < 1e-4
    # The opposite sign would be far off: the test tells the two apart.
    flipped = np.abs(-imported.motion - ours.motion)[inside].max()
    assert flipped > 10


@needs_bpy
def test_textures_match(ctx):
    scene = bl.scenes.textured_spin()
    cycles = bl.blender.render(scene, SIZE, samples=64).color
    antialiased = ctx.reference(scene, SIZE, samples=128, antialias=True).color
    assert bl.metrics.psnr(antialiased, cycles) > 33
    flipped = bl.scenes.textured_spin()
    for obj in flipped.objects:  # v -> 1 - v: what a texture stored upside down would show
        if obj.material.texture is not None:
            rgba = obj.material.texture_rgba().astype(np.float32)
            obj.material = bl.Material(obj.material.color, np.ascontiguousarray(rgba[::-1]))
    upside_down = ctx.reference(flipped, SIZE, samples=128, antialias=True).color
    assert bl.metrics.psnr(antialiased, cycles) > bl.metrics.psnr(upside_down, cycles) + 3


@needs_bpy
def test_eevee_renders_a_motion_blurred_frame(ctx):
    scene = square_scene(distance_px=30.0 * SIZE[1] / 90)
    eevee = bl.blender.render(scene, SIZE, engine="EEVEE", samples=8, steps=8)
    assert eevee.settings["motion_blur_steps"] == 8 and "EEVEE on " in eevee.device
    antialiased = ctx.reference(scene, SIZE, samples=256, antialias=True).color
    assert bl.metrics.psnr(antialiased, eevee.color) > 25
    sharp = ctx.render(scene, SIZE).color
    assert bl.metrics.psnr(antialiased, eevee.color) > bl.metrics.psnr(antialiased, sharp)


@pytest.mark.parametrize(
    "material, match",
    [
        (bl.Material((1, 1, 1), specular=0.5), "Blinn-Phong specular"),
        (bl.Material.hatching(), "hatched material"),
    ],
)
def test_what_blender_cannot_match_is_refused(material, match):
    scene = square_scene(10.0)
    scene.add(bl.mesh.box(), material)
    with pytest.raises(ValueError, match=match):
        bl.blender.render(scene, SIZE)


@needs_bpy
def test_a_skinned_mesh_blurs_by_its_baked_deformation(ctx):
    scene = bl.scenes.skinned_arm()
    for obj in scene.objects:
        obj.material.specular = 0.0  # Lambert: Blender has no Blinn-Phong
    cycles = bl.blender.render(scene, SIZE, samples=64).color
    antialiased = ctx.reference(scene, SIZE, samples=128, antialias=True).color
    sharp = ctx.render(scene, SIZE).color  # no deformation blur: what a rigid export would give
    assert bl.metrics.psnr(antialiased, cycles) > 45  # measured 57 dB at 160x90, 128 spp
    assert bl.metrics.psnr(antialiased, cycles) > bl.metrics.psnr(antialiased, sharp) + 10


def test_without_bpy_the_error_says_how_to_install(monkeypatch):
    monkeypatch.setattr(bl.blender, "available", lambda: False)
    with pytest.raises(ImportError, match=r"blurlab blender install.*Python 3\.11.*unchanged"):
        bl.blender.render(square_scene(10.0), SIZE)


def pip_freeze() -> str:
    return subprocess.run(
        [sys.executable, "-m", "pip", "freeze"], capture_output=True, text=True, check=True
    ).stdout


@pytest.mark.blender_install
def test_installing_blender_support_leaves_pip_freeze_unchanged(tmp_path):
    """`blurlab blender install` puts bpy and the NumPy it pins in an environment of its own
    (a fresh folder here; pip's cache spares the download): this environment's packages stay
    as they were, and the private one imports bpy."""
    try:
        environment.find_python311()
    except RuntimeError as why:
        pytest.skip(str(why))
    before = pip_freeze()
    env = {**os.environ, "BLURLAB_CACHE_DIR": str(tmp_path)}
    command = [sys.executable, "-m", "blurlab", "blender", "install"]
    done = subprocess.run(command, capture_output=True, text=True, env=env, timeout=1800)
    assert done.returncode == 0, done.stderr[-3000:]
    assert pip_freeze() == before
    private = tmp_path / "environments" / environment.ENVIRONMENT / "bin" / "python"
    probe = "import bpy, numpy; print(bpy.app.version_string, numpy.__version__)"
    versions = subprocess.run([private, "-c", probe], capture_output=True, text=True)
    assert versions.returncode == 0, versions.stderr[-2000:]
    assert versions.stdout.split()[0].startswith("5.0")
    status = subprocess.run(
        [sys.executable, "-m", "blurlab", "blender", "status"], capture_output=True, text=True,
        env=env,
    )  # fmt: skip
    assert str(private) in status.stdout


def test_an_interpreter_without_bpy_is_an_import_error(tmp_path):
    python = fake_python(tmp_path, "echo \"ModuleNotFoundError: No module named 'bpy'\"; exit 1")
    before = leftovers()
    with pytest.raises(ImportError, match="blurlab.blender"):
        bl.blender.render(square_scene(10.0), SIZE, python=python)
    assert leftovers() == before


def test_a_crash_comes_back_with_the_log_and_leaves_nothing(tmp_path):
    python = fake_python(tmp_path, 'echo "building the scene in $2"; kill -SEGV $$')
    before = leftovers()
    with pytest.raises(bl.blender.BlenderError, match="crashed.*SIGSEGV") as error:
        bl.blender.render(square_scene(10.0), SIZE, python=python)
    assert "building the scene in" in str(error.value)  # Blender's log tail
    assert leftovers() == before


def test_a_child_that_hangs_is_killed(tmp_path):
    marker = tmp_path / "still running"
    python = fake_python(tmp_path, f'echo started; sleep 3; touch "{marker}"')
    before = leftovers()
    with pytest.raises(bl.blender.BlenderError, match="(?s)did not finish within 0.5 s.*started"):
        bl.blender.render(square_scene(10.0), SIZE, python=python, timeout=0.5)
    assert leftovers() == before
    os.system("sleep 3.5")  # the killed child would have written the marker by now
    assert not marker.exists()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"engine": "LUXCORE"}, "engine must be 'CYCLES' or 'EEVEE'"),
        ({"samples": 0}, "samples must be an integer"),
        ({"steps": 8}, "steps must be an integer in 1..7"),
        ({"size": (0, 10)}, r"size \(0, 10\) must be two integers in 1\.\.16384"),
        ({"size": "ab"}, "size must be"),
        ({"shutter": (1.0, 1.0)}, "longer than 0"),
        ({"instant": 2.0}, "outside the shutter"),
        ({"timeout": 0}, "timeout"),
        ({"engine": "EEVEE", "passes": "passes.exr"}, "Cycles only"),
        ({"passes": "no such folder/passes.exr"}, "existing folder"),
        ({"passes": 3}, "file path"),
    ],
)
def test_bad_arguments(kwargs, match):
    args = {"size": SIZE, **kwargs}
    with pytest.raises(ValueError, match=match):
        bl.blender.render(square_scene(10.0), **args)


@needs_bpy
def test_study_scores_eevee_as_a_peer(ctx, tmp_path):
    report = run_study(
        ctx,
        ["crossing", "skinned_arm"],
        SIZE,
        tmp_path,
        reference_samples=16,
        metrics=("psnr", "psnr_aa"),
        grids={pick(params=("taps",)): {"taps": [4]}},
        progress=False,
        peer_names=("eevee",),
    )
    peers = pd.read_csv(tmp_path / "peers.csv")
    crossing = peers[peers["scene"] == "crossing"]
    assert list(crossing["method"]) == [label for label, *_ in EEVEE_ROWS]
    assert crossing["psnr"].between(15, 80).all() and crossing["psnr_aa"].between(15, 80).all()
    assert crossing["time"].str.contains("s Blender wall time").all()
    assert crossing["time"].str.contains("EEVEE on ").all()
    arm = peers[peers["scene"] == "skinned_arm"]
    assert arm["note"].str.contains("Blinn-Phong").all() and arm["psnr"].isna().all()
    assert "Peers: Blender's EEVEE" in report.read_text()


def test_unknown_or_unavailable_peers_fail_before_any_work(monkeypatch):
    with pytest.raises(ValueError, match="unknown peers"):
        check_peers(("cycles_x",))
    monkeypatch.setattr(bl.blender, "available", lambda: False)
    with pytest.raises(ImportError, match="blurlab blender install"):
        check_peers(("eevee",))
