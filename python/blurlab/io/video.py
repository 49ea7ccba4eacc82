"""Sequences of frames as files (docs/spec.md §21.5): an EXR per frame (OpenImageIO), an MP4
(imageio-ffmpeg, the optional extra `video`), or a looping animated WebP or GIF (Pillow). The
arrays are (N, H, W, 3 or 4) linear colour; the 8-bit formats encode it as sRGB, clipped."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from . import images as io

ANIMATIONS = (".gif", ".webp")
MOVIES = (".mp4",)


def check_frames(frames) -> np.ndarray:
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[0] < 1 or frames.shape[3] not in (3, 4) or not frames.size:
        raise ValueError(
            f"blurlab.io.video: frames must be an (N, H, W, 3 or 4) array, not {frames.shape}"
        )
    return frames


def write_exr_sequence(folder, frames, stem: str = "frame") -> list[Path]:
    """One float32 EXR per frame, `folder`/`stem`_0000.exr …; returns the paths."""
    frames = check_frames(frames)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    digits = max(4, len(str(len(frames) - 1)))
    return [
        io.write(folder / f"{stem}_{i:0{digits}d}.exr", np.asarray(frame, np.float32))
        for i, frame in enumerate(frames)
    ]


def srgb_frames(frames) -> np.ndarray:
    """(N, H, W, 3) uint8 sRGB of linear frames, cropped to even sizes (what H.264 takes)."""
    frames = check_frames(frames)
    height, width = frames.shape[1] - frames.shape[1] % 2, frames.shape[2] - frames.shape[2] % 2
    return io.srgb8(np.asarray(frames[:, :height, :width, :3], np.float32))


def write_mp4(path, frames, fps: float) -> Path:
    """An H.264 MP4 at `fps`, through imageio-ffmpeg (`pip install blurlab[video]`). Frames of
    odd width or height lose their last column or row."""
    try:
        import imageio_ffmpeg
    except ImportError:
        raise ImportError(
            "blurlab.io.video: MP4 needs imageio-ffmpeg: pip install 'blurlab[video]'"
        ) from None
    path = Path(path)
    encoded = srgb_frames(frames)
    if encoded.shape[1] < 2 or encoded.shape[2] < 2:
        raise ValueError("blurlab.io.video: an MP4 needs frames of at least 2 x 2 pixels")
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".mp4", dir=path.parent)
    os.close(fd)
    try:
        writer = imageio_ffmpeg.write_frames(
            tmp_name, (encoded.shape[2], encoded.shape[1]), fps=float(fps), macro_block_size=2
        )
        writer.send(None)
        for frame in encoded:
            writer.send(np.ascontiguousarray(frame))
        writer.close()
        io.publish(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


def write_animation(path, frames, fps: float) -> Path:
    """A looping animated WebP (lossless) or GIF of the frames at `fps`, through Pillow."""
    from PIL import Image

    path = Path(path)
    if path.suffix.lower() not in ANIMATIONS:
        raise ValueError(
            f"blurlab.io.video: an animation is one of {ANIMATIONS}, not {path.name!r}"
        )
    frames = check_frames(frames)
    images = [Image.fromarray(frame) for frame in io.srgb8(np.asarray(frames[..., :3], np.float32))]
    duration = max(20, round(1000.0 / fps))  # milliseconds a frame; browsers floor GIFs at 20
    # Lossless WebP's quality is its compression effort: 0 encoded six 3840x1080 test frames
    # 2.4x faster than the default, for 10 % more bytes and the same pixels.
    options = {"lossless": True, "quality": 0} if path.suffix.lower() == ".webp" else {}
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        images[0].save(
            tmp_name,
            save_all=True,
            append_images=images[1:],
            duration=duration,
            loop=0,
            **options,
        )
        io.publish(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


def write(path, frames, fps: float) -> Path | list[Path]:
    """The frames as `path` says: a folder (no suffix) of EXRs, an .mp4, a .gif or a .webp."""
    suffix = Path(path).suffix.lower()
    if suffix == "":
        return write_exr_sequence(path, frames)
    if suffix in MOVIES:
        return write_mp4(path, frames, fps)
    if suffix in ANIMATIONS:
        return write_animation(path, frames, fps)
    raise ValueError(
        f"blurlab.io.video: write a folder of EXRs (no suffix), or one of {MOVIES + ANIMATIONS}, "
        f"not {Path(path).name!r}"
    )
