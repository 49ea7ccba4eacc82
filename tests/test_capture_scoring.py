"""Scoring from files (docs/engine_output.md, docs/spec.md §16.6): captured sequences from a
file pattern, read lazily from the pattern's folder only, and `blurlab study --capture`, which
scores every method on the captured G-buffer against a reference from a file with the engine's
own output as a row beside them; each bad input is a clear error naming the file."""

from __future__ import annotations

import html
import os
import re
import shlex
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import blurlab as bl
from blurlab import cli
from blurlab.blender.crosscheck import box_scene
from blurlab.io import capture, images
from blurlab.metrics import temporal_instability
from blurlab.studies import capture_study, peers
from blurlab.studies.capture_study import capture_grids, run_capture_study

ROOT = Path(__file__).resolve().parents[1]
SIZE = (64, 36)
SCENE = "fan"
FRAMES = 3
# A capture as Blender writes it: its multi-layer names, its Vector pass's convention.
CHANNELS = [f"ViewLayer.Combined.{c}" for c in "RGBA"] + ["ViewLayer.Depth.Z"]
CHANNELS += [f"ViewLayer.Vector.{c}" for c in "XYZW"]
# Methods chosen by what they are, not by name: those whose defaults run on a capture (the
# first one's output stands for an engine's), and one whose defaults read the G-buffer at
# shutter close, which a capture does not have.
AT_CENTRE = [name for name in bl.methods() if capture_grids({name: {}})[0]]
ENGINE, OTHER = AT_CENTRE[:2]
AT_CLOSE = next(
    name for name in bl.methods() if "shutter close" in capture_grids({name: {}})[1].get(name, "")
)


def write_capture(path: Path, frame) -> Path:
    vector = capture.motion_from_blurlab(frame.motion, "blender")
    layers = np.concatenate([frame.color, frame.depth[..., None], vector], axis=2)
    return bl.io.write(path, layers.astype(np.float32), channel_names=CHANNELS)


@pytest.fixture(scope="module")
def shot(ctx, tmp_path_factory):
    """FRAMES consecutive frames of SCENE as files: the G-buffer (shot.####.exr), the
    reference of each frame's shutter (reference.####.exr) and ENGINE's output on it
    (engine.####.exr), numbered from 7; and the arrays they hold."""
    folder = tmp_path_factory.mktemp("shot")
    scene = bl.scenes.get(SCENE)
    arrays = {"color": [], "reference": [], "engine": []}
    for i in range(FRAMES):
        shutter = (0.25 * i, 0.25 * i + 1.0)
        frame = ctx.render(scene, SIZE, shutter)
        reference = ctx.reference(scene, SIZE, shutter, samples=8, progress=False).color
        engine = bl.blur(ctx, frame, ENGINE).color
        number = f"{7 + i:04d}"
        write_capture(folder / f"shot.{number}.exr", frame)
        bl.io.write(folder / f"reference.{number}.exr", reference)
        bl.io.write(folder / f"engine.{number}.exr", engine)
        arrays["color"].append(frame.color)
        arrays["reference"].append(reference)
        arrays["engine"].append(engine)
    return folder, {k: np.stack(v) for k, v in arrays.items()}


# Captured sequences ---------------------------------------------------------------------------


def test_a_pattern_gives_its_frames_in_order_each_read_only_when_asked_for(shot, monkeypatch):
    folder, arrays = shot
    # Files the pattern does not name: another padding, another prefix, another suffix.
    for decoy in ("shot.07.exr", "shot.00010.exr", "take.0008.exr", "shot.0008.exr.bak"):
        (folder / decoy).write_bytes(b"not an image")
    reads = []
    real = bl.io.read_channels
    monkeypatch.setattr(images, "read_channels", lambda path: reads.append(path) or real(path))
    frames = bl.capture.sequence(str(folder / "shot.####.exr"))
    assert frames.numbers == (7, 8, 9) and len(frames) == FRAMES
    assert [p.name for p in frames.paths] == ["shot.0007.exr", "shot.0008.exr", "shot.0009.exr"]
    assert reads == [] and frames.size() == SIZE and reads == []  # headers only
    second = bl.Frame(**frames[1])
    assert [Path(p).name for p in reads] == ["shot.0008.exr"]
    assert np.array_equal(second.color, arrays["color"][1])
    one = bl.capture.sequence(folder / "reference.0008.exr")
    assert len(one) == 1 and np.array_equal(one.color(0), arrays["reference"][1])
    for decoy in ("shot.07.exr", "shot.00010.exr", "take.0008.exr", "shot.0008.exr.bak"):
        (folder / decoy).unlink()


def test_a_pattern_reads_only_its_own_folders_regular_files(shot, tmp_path):
    folder, _ = shot
    (tmp_path / "shot.0001.exr").symlink_to(folder / "shot.0007.exr")
    with pytest.raises(ValueError, match=r"shot\.0001\.exr matches .* not a regular file"):
        bl.capture.sequence(tmp_path / "shot.####.exr")
    with pytest.raises(ValueError, match="goes in the file name, not in a folder"):
        bl.capture.sequence(tmp_path / "take.##" / "shot.####.exr")
    with pytest.raises(ValueError, match="2 runs of #"):
        bl.capture.sequence(tmp_path / "shot.##.##.exr")


def test_a_pattern_matching_nothing_or_missing_a_frame_is_refused(shot, tmp_path):
    folder, _ = shot
    with pytest.raises(FileNotFoundError, match=r"no file in .* matches 'nothing\.####\.exr'"):
        bl.capture.sequence(folder / "nothing.####.exr")
    with pytest.raises(FileNotFoundError, match=r"no such file: .*missing\.exr"):
        bl.capture.sequence(folder / "missing.exr")
    with pytest.raises(FileNotFoundError, match="no such folder"):
        bl.capture.sequence(tmp_path / "gone" / "shot.####.exr")
    for number in (1, 2, 4):
        (tmp_path / f"gap.{number:04d}.exr").write_bytes(b"")
    with pytest.raises(FileNotFoundError, match=r"1 missing, the first .*gap\.0003\.exr"):
        bl.capture.sequence(tmp_path / "gap.####.exr")


def test_an_unknown_convention_or_option_is_refused_listing_the_known_ones(shot):
    folder, _ = shot
    pattern = str(folder / "shot.####.exr")
    with pytest.raises(ValueError, match=r"shot\.####\.exr.*one of \('blurlab', 'blender'"):
        bl.capture.sequence(pattern, convention="unreal4")
    with pytest.raises(TypeError, match=r"unknown options \['fps'\]"):
        bl.capture.sequence(pattern, fps=24)


# Scoring from files ---------------------------------------------------------------------------


def scored(ctx, folder: Path, number: str, out: Path, **options) -> pd.DataFrame:
    """results.csv, by method, of the capture study on the shot's frame `number` (or "####",
    the sequence): its capture, reference and engine output."""
    files = [folder / f"{what}.{number}.exr" for what in ("shot", "reference", "engine")]
    run_capture_study(ctx, *files, convention="blender", out=out, **options)
    return pd.read_csv(out / "results.csv").set_index("method")


def test_the_engines_output_is_a_row_scored_as_the_methods_are(ctx, shot, tmp_path):
    folder, _ = shot
    grids = {ENGINE: {}, AT_CLOSE: {}}
    table = scored(ctx, folder, "0007", tmp_path, grids=grids, repeats=1, engine_name="my_engine")
    assert list(table.index) == [ENGINE, "my_engine"]  # AT_CLOSE does not run
    # The engine's file holds ENGINE's output on the same G-buffer: the same scores, computed
    # on the GPU for the method and in NumPy for the file.
    for metric, tolerance in (("psnr", 1e-3), ("ssim", 1e-4), ("flip", 1e-3)):
        assert table.loc["my_engine", metric] == pytest.approx(
            table.loc[ENGINE, metric], abs=tolerance
        )
    assert 15 < table.loc[ENGINE, "psnr"] < 80 and table.loc[ENGINE, "total_ms"] > 0
    assert np.isnan(table.loc["my_engine", "total_ms"])
    assert table.loc["my_engine", "source"].endswith("engine.0007.exr")
    report = html.unescape((tmp_path / "report.html").read_text())
    assert "my_engine" in report and f"{AT_CLOSE}: expects the G-buffer at shutter close" in report
    assert "TAA" in report and (tmp_path / "shot_my_engine.png").is_file()


def test_a_sequence_adds_the_temporal_metric_over_its_frames(ctx, shot, tmp_path):
    folder, arrays = shot
    table = scored(ctx, folder, "####", tmp_path, grids={ENGINE: {}}, repeats=0)
    frames = pd.read_csv(tmp_path / "frames.csv")
    assert (table["frames"] == FRAMES).all() and len(frames) == 2 * FRAMES
    engine = table.loc["engine_output"]
    # The frame pairs' shares add up to the metric on the whole sequence.
    pairs = (arrays["reference"], arrays["engine"])
    whole = temporal_instability(*pairs)
    assert engine["temporal_instability"] == pytest.approx(whole, rel=1e-9)
    assert table.loc[ENGINE, "temporal_instability"] == pytest.approx(whole, abs=1e-4)
    per_frame = frames[frames["method"] == "engine_output"]["psnr"]
    # PSNR over the frames is that of their mean squared error, as study --sequence takes it.
    each = [bl.metrics.psnr(a, b) for a, b in zip(*pairs, strict=True)]
    assert per_frame.to_list() == pytest.approx(each, abs=1e-9)
    mse = np.mean([10 ** (-value / 10) for value in each])
    assert engine["psnr"] == pytest.approx(10 * np.log10(1 / mse), abs=1e-9)
    assert per_frame.nunique() == FRAMES  # each frame scored against its own reference


def test_outputs_past_the_memory_bound_are_scored_in_further_passes(ctx, shot, tmp_path):
    """With room for one configuration's outputs at a time, each configuration gets a pass of
    its own over the files, and the same numbers."""
    folder, _ = shot
    grids = {ENGINE: {}, OTHER: {}}
    together = scored(ctx, folder, "####", tmp_path / "a", grids=grids, repeats=0)
    reads = []
    real = bl.io.read_channels
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(capture_study, "KEPT_BYTES", 1)
        patch.setattr(images, "read_channels", lambda path: reads.append(path) or real(path))
        apart = scored(ctx, folder, "####", tmp_path / "b", grids=grids, repeats=0)
    shots = [Path(p).name for p in reads if Path(p).name.startswith("shot.")]
    assert len(shots) == 2 * FRAMES  # each capture frame read once per configuration
    columns = ["psnr", "ssim", "flip", "temporal_instability"]
    pd.testing.assert_frame_equal(together[columns], apart[columns])


def documented_capture_command() -> str:
    """The `blurlab study --capture` line of docs/engine_output.md."""
    lines = [
        line.strip().removeprefix("$ ").split("  #")[0]
        for line in (ROOT / "docs" / "engine_output.md").read_text().splitlines()
        if line.strip().startswith("$ blurlab study --capture")
    ]
    assert len(lines) == 1, lines
    return lines[0]


def test_the_documented_command_scores_every_method_that_runs_on_a_capture(
    shot, tmp_path, monkeypatch
):
    folder, _ = shot
    for source, target in (("shot", "shot"), ("reference", "cycles"), ("engine", "engine")):
        for i in range(FRAMES):
            os.link(folder / f"{source}.{7 + i:04d}.exr", tmp_path / f"{target}.{1 + i:04d}.exr")
    words = shlex.split(documented_capture_command())
    monkeypatch.chdir(tmp_path)
    assert cli.main(words[1:]) == 0
    out = tmp_path / words[words.index("--out") + 1]
    table = pd.read_csv(out / "results.csv")
    kept, left_out = capture_grids()
    name = words[words.index("--engine-name") + 1] if "--engine-name" in words else None
    assert len(table) == sum(len(points) for points in kept.values()) + 1
    assert set(table["method"]) == set(kept) | {name or "engine_output"}
    assert table["psnr"].notna().all() and (table["frames"] == FRAMES).all()
    report = html.unescape((out / "report.html").read_text())
    assert all(f"{method}: " in report for method in left_out)


# Bad input: each a clear error naming the file -----------------------------------------------


@pytest.fixture
def odd_files(ctx, shot, tmp_path):
    """A reference and an engine output of another size, and one of another frame count."""
    folder, arrays = shot
    small = np.ascontiguousarray(arrays["reference"][0][::2, ::2])
    bl.io.write(tmp_path / "small.exr", small)
    for i in range(FRAMES - 1):
        bl.io.write(tmp_path / f"short.{7 + i:04d}.exr", arrays["reference"][i])
    return folder, tmp_path


@pytest.mark.parametrize(
    "argument, path, message",
    [
        ("--reference", "small.exr", r"the reference small\.exr is 32x18, the capture shot"),
        ("--engine-output", "small.exr", r"the engine output small\.exr is 32x18, the capture"),
        ("--reference", "short.####.exr", r"short\.####\.exr has 2 frames, the capture .* 3"),
        ("--reference", "absent.exr", r"no such file: .*absent\.exr"),
        ("--engine-output", "absent.####.exr", r"no file in .* matches 'absent\.####\.exr'"),
    ],
)
def test_mismatched_or_missing_inputs_are_one_line_naming_the_file(
    odd_files, argument, path, message, capsys
):
    folder, odd = odd_files
    given = {
        "--capture": str(folder / "shot.####.exr"),
        "--reference": str(folder / "reference.####.exr"),
        argument: str(odd / path),
    }
    if path == "small.exr":  # a single frame against one
        given["--capture"] = str(folder / "shot.0007.exr")
        given.setdefault("--reference", str(folder / "reference.0007.exr"))
        if argument == "--engine-output":
            given["--reference"] = str(folder / "reference.0007.exr")
    words = ["study", *[w for pair in given.items() for w in pair], "--out", str(odd / "out")]
    with pytest.raises(SystemExit) as stopped:
        cli.main(words)
    assert stopped.value.code == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and re.search(message, error), error
    assert not (odd / "out" / "results.csv").exists()


def test_an_unknown_convention_is_one_line_listing_the_known_ones(shot, capsys):
    folder, _ = shot
    words = ["study", "--capture", str(folder / "shot.0007.exr")]
    words += ["--reference", str(folder / "reference.0007.exr"), "--convention", "unity5"]
    with pytest.raises(SystemExit):
        cli.main(words)
    error = capsys.readouterr().err
    assert "shot.0007.exr" in error and "not 'unity5'" in error
    assert all(repr(c) in error for c in capture.MOTION_CONVENTIONS), error


@pytest.mark.parametrize(
    "words, message",
    [
        (["--convention", "blender"], "--convention is for --capture"),
        (["--capture", "x.exr"], "needs --reference PATH"),
        (["--capture", "x.exr", "--reference", "y.exr", "--peers", "eevee"], "--peers are for"),
    ],
)
def test_capture_options_go_together(words, message, capsys):
    with pytest.raises(SystemExit):
        cli.main(["study", *words])
    assert message in capsys.readouterr().err


# Blender as the engine ------------------------------------------------------------------------

needs_bpy = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not set up (blurlab blender install)"
)
BLENDER_SIZE = (80, 45)
BLENDER_SAMPLES = 256  # Cycles' samples per pixel, and N of blurlab's references


@needs_bpy
def test_blenders_files_give_the_eevee_row_that_peers_eevee_gives(ctx, tmp_path):
    """Blender writes the capture (Combined, Depth and Vector at the shutter's centre), EEVEE's
    motion-blurred render and a Cycles reference of the same shutter; scored from those files,
    the EEVEE row is --peers eevee's row (blurlab.studies.peers.peer_rows)."""
    scene, size = box_scene(), BLENDER_SIZE
    bl.blender.render(scene, size, engine="CYCLES", passes=tmp_path / "passes.exr")
    eevee = bl.blender.render(scene, size, engine="EEVEE", samples=1, steps=1).color
    cycles = bl.blender.render(scene, size, engine="CYCLES", samples=BLENDER_SAMPLES).color
    bl.io.write(tmp_path / "eevee.exr", eevee)
    bl.io.write(tmp_path / "cycles.exr", cycles)
    references = {
        aa: ctx.reference(scene, size, samples=BLENDER_SAMPLES, antialias=aa, progress=False)
        for aa in (False, True)
    }
    bl.io.write(tmp_path / "blurlab.exr", references[False].color)
    label = peers.EEVEE_ROWS[0][0]  # the post-process filter alone: 1 sample, 1 step
    (peer,) = peers.peer_rows(
        ctx, "box", scene, size, references.__getitem__, ("psnr", "psnr_aa"), [(label, 1, 1)]
    )

    def eevee_row(reference: str) -> pd.Series:
        out = tmp_path / reference
        run_capture_study(
            ctx,
            tmp_path / "passes.exr",
            tmp_path / f"{reference}.exr",
            tmp_path / "eevee.exr",
            engine_name="eevee",
            convention="blender",
            out=out,
            grids={ENGINE: {}, OTHER: {}},
            repeats=0,
        )
        table = pd.read_csv(out / "results.csv").set_index("method")
        assert table["psnr"].between(15, 80).all()  # the methods ran on Blender's passes
        return table.loc["eevee"]

    # Against blurlab's own reference, from a file: --peers eevee's PSNR.
    assert eevee_row("blurlab")["psnr"] == pytest.approx(peer["psnr"], abs=0.01)
    # Cycles' image is box-filtered over the pixel: the antialiased reference (§11). Against
    # it the row is --peers eevee's psnr_aa; the two references are two estimates of one
    # image, so by the triangle inequality the PSNRs differ by at most 20 log10(1 + d / e),
    # d and e the RMS differences of Cycles and of EEVEE from blurlab's reference.
    against_cycles = eevee_row("cycles")["psnr"]
    d_over_e = 10 ** ((peer["psnr_aa"] - bl.metrics.psnr(references[True].color, cycles)) / 20)
    assert abs(against_cycles - peer["psnr_aa"]) <= 20 * np.log10(1 + d_over_e)
    assert against_cycles == pytest.approx(peer["psnr_aa"], abs=0.01)  # measured: 0.0005 dB


def test_a_reference_with_nan_or_an_engine_name_of_a_method_is_refused(ctx, shot, tmp_path):
    folder, arrays = shot
    broken = arrays["reference"][0].copy()
    broken[3, 5, 1] = np.nan
    bl.io.write(tmp_path / "nan.exr", broken)
    files = (folder / "shot.0007.exr", tmp_path / "nan.exr", folder / "engine.0007.exr")
    with pytest.raises(ValueError, match=r"the reference nan\.exr has 1 NaN or infinite"):
        run_capture_study(ctx, *files, convention="blender", out=tmp_path / "a", grids={})
    with pytest.raises(ValueError, match=f"no method's name, not '{ENGINE}'"):
        run_capture_study(ctx, *files, engine_name=ENGINE, out=tmp_path / "b")
    assert not (tmp_path / "a" / "results.csv").exists()
