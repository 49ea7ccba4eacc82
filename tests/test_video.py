"""Sequences as files (blurlab.io.video, docs/spec.md §21.5): EXRs that read back bit for bit,
looping animations with one image per frame, and MP4 where imageio-ffmpeg is installed."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import blurlab as bl
from blurlab.io import video


@pytest.fixture(scope="module")
def frames():
    rng = np.random.default_rng(3)
    return rng.random((3, 10, 14, 4)).astype(np.float32)


def test_an_exr_sequence_reads_back_bit_for_bit(tmp_path, frames):
    paths = video.write(tmp_path / "run", frames, 60)
    assert [p.name for p in paths] == ["frame_0000.exr", "frame_0001.exr", "frame_0002.exr"]
    assert all(np.array_equal(bl.io.read(p), f) for p, f in zip(paths, frames, strict=True))


@pytest.mark.parametrize("suffix", video.ANIMATIONS)
def test_an_animation_loops_with_one_image_per_frame(tmp_path, frames, suffix):
    path = video.write(tmp_path / f"run{suffix}", frames, 30)
    with Image.open(path) as image:
        assert image.n_frames == 3 and image.size == (14, 10)
        assert image.info.get("loop") == 0
        if suffix == ".webp":  # lossless: the first frame is its sRGB encoding exactly
            first = np.asarray(image.convert("RGB"))
            assert np.array_equal(first, bl.io.srgb8(frames[0, ..., :3]))


def test_an_mp4_holds_every_frame(tmp_path, frames):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    path = video.write(tmp_path / "run.mp4", frames, 24)
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = reader.__next__()
    assert meta["size"] == (14, 10) and sum(1 for _ in reader) == 3


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda p, f: video.write(p / "run.avi", f, 30), r"or one of \('.mp4', '.gif'"),
        (lambda p, f: video.write(p / "run.gif", f[0], 30), r"\(N, H, W, 3 or 4\) array"),
    ],
)
def test_bad_requests_say_what_is_allowed(tmp_path, frames, call, match):
    with pytest.raises(ValueError, match=match):
        call(tmp_path, frames)
    assert not list(tmp_path.iterdir())  # nothing half-written


def test_a_run_writes_its_worst_frames_beside_the_reference(ctx, tmp_path):
    seq = bl.sequence(ctx, bl.scenes.fan(), (32, 18), frames=4, reference_samples=4)
    run = seq.run(None, "blur_then_taa")
    worst = run.worst_frames("psnr", 2)
    assert (
        len(worst) == 2
        and run.scores["psnr"][worst].max() <= np.delete(run.scores["psnr"], worst).min()
    )
    path = run.write(tmp_path / "worst.webp", worst)
    with Image.open(path) as image:
        assert image.n_frames == 2 and image.size == (64, 18)
