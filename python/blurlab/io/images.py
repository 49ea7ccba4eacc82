"""Image files through OpenImageIO: EXR for float buffers, PNG for 8-bit sRGB pictures.

``write`` goes through a temporary file in the destination folder and an atomic rename, so a
failed write never leaves a partial file behind.
"""

from __future__ import annotations

import functools
import os
import tempfile
from pathlib import Path

import numpy as np

FLOAT_FORMATS = (".exr",)
EIGHT_BIT_FORMATS = (".png",)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) on linear values clipped to [0, 1]."""
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def srgb_to_linear(srgb: np.ndarray) -> np.ndarray:
    """Inverse of :func:`linear_to_srgb`."""
    c = np.asarray(srgb, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, np.power((c + 0.055) / 1.055, 2.4))


def _srgb8_exact(linear) -> np.ndarray:
    return np.round(linear_to_srgb(linear) * 255.0).astype(np.uint8)


# srgb8 by table: where in [0, 1] each 8-bit code starts, and a 2^16-bin table of the code at
# each bin's start. Codes are at least 3e-4 apart in linear light (at the dark end, where sRGB
# is steepest), so a bin 1.5e-5 wide holds at most one step, and one comparison with the next
# code's start finishes the rounding: the same bytes as the transfer function in float64,
# 10-40x faster on a 1080p picture (tests/test_io.py compares them at every step).
SRGB8_BINS = 1 << 16


@functools.lru_cache(maxsize=1)
def _srgb8_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(starts64, starts32, bins): starts64[k - 1] is the least float64 whose code is >= k
    (k = 1..255), found by bisecting on the bit patterns of [0, 1] with the float64 formula;
    starts32 the least float32 at or above it, then +inf (no code 256); bins[i] the code of
    i / SRGB8_BINS."""
    codes = np.arange(1, 256)
    low = np.zeros(255, np.int64)  # bit patterns: low's code < k <= high's code
    high = np.full(255, np.float64(1.0).view(np.int64))
    while (high - low > 1).any():
        middle = (low + high) // 2
        reached = _srgb8_exact(middle.view(np.float64)) >= codes
        high = np.where(reached, middle, high)
        low = np.where(reached, low, middle)
    starts64 = high.view(np.float64)
    starts32 = starts64.astype(np.float32)
    starts32 = np.where(starts32 < starts64, np.nextafter(starts32, np.float32(2)), starts32)
    starts32 = np.append(starts32, np.float32(np.inf)).astype(np.float32)
    grid = np.arange(SRGB8_BINS + 1, dtype=np.float64) / SRGB8_BINS
    bins = np.searchsorted(starts64, grid, side="right").astype(np.uint8)
    return starts64, starts32, bins


def srgb8(linear: np.ndarray) -> np.ndarray:
    """8-bit sRGB of linear colour (clipped to [0, 1], rounded to nearest; NaN gives 0): what
    a PNG holds."""
    linear = np.asarray(linear)
    starts64, starts32, bins = _srgb8_tables()
    if linear.dtype != np.float32:  # float64 (or anything else): compare in float64
        clipped = np.nan_to_num(np.clip(np.asarray(linear, np.float64), 0.0, 1.0), nan=0.0)
        return np.searchsorted(starts64, clipped, side="right").astype(np.uint8)
    # fmax before fmin sends NaN to 0; the scaling by a power of two is exact in float32.
    clipped = np.fmin(np.fmax(linear, np.float32(0.0)), np.float32(1.0))
    code = bins[(clipped * np.float32(SRGB8_BINS)).astype(np.int32)]
    code += clipped >= starts32[code]  # never past 255: starts32[255] is +inf
    return code


def _oiio():
    import OpenImageIO as oiio

    return oiio


def write(
    path: str | os.PathLike, array: np.ndarray, channel_names=None, png_compression: int = 6
) -> Path:
    """Writes ``array`` ((H, W) or (H, W, C)) to ``path``; returns the path.

    - ``.exr``: float32 stays float32, float16 stays half; uint8 is written as float32 / 255.
      ``channel_names`` (one per channel, e.g. "motion.X") names the channels of a multi-layer
      file; by default OpenImageIO names them R, G, B, A.
    - ``.png``: float arrays are linear color, clipped to [0, 1] and sRGB-encoded to 8 bits;
      uint8 arrays are taken as already encoded and written as they are. ``png_compression``:
      zlib's level, 0 (none) to 9; 1 encodes a render in about 2/3 of the default 6's time
      for files about 30 % larger (the study's report uses it).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FLOAT_FORMATS + EIGHT_BIT_FORMATS:
        raise ValueError(
            f"blurlab.io.write: cannot write {path.name!r}; allowed extensions are "
            + ", ".join(FLOAT_FORMATS + EIGHT_BIT_FORMATS)
        )
    if not isinstance(array, np.ndarray):
        raise TypeError(
            f"blurlab.io.write: array must be a numpy.ndarray, not {type(array).__name__}"
        )
    if array.ndim not in (2, 3) or array.size == 0:
        raise ValueError(
            f"blurlab.io.write: array of shape {array.shape} is not a non-empty (H, W) or (H, W, C)"
        )
    if array.dtype.name not in ("uint8", "float16", "float32", "float64"):
        raise TypeError(
            f"blurlab.io.write: dtype {array.dtype} not supported; use uint8, float16, float32 "
            "or float64"
        )
    if (
        isinstance(png_compression, bool)
        or not isinstance(png_compression, int)
        or not 0 <= png_compression <= 9
    ):
        raise ValueError(
            f"blurlab.io.write: png_compression is an integer 0 to 9, not {png_compression!r}"
        )
    if suffix == ".png" and array.ndim == 3 and array.shape[2] > 4:
        raise ValueError(f"blurlab.io.write: PNG takes 1 to 4 channels, not {array.shape[2]}")
    if array.dtype.kind == "f" and not np.isfinite(array).all() and suffix == ".png":
        raise ValueError("blurlab.io.write: array has NaN or inf values, which PNG cannot hold")
    data = _encode(array, suffix)
    if data.ndim == 2:  # OpenImageIO reads a 2-D array's second axis as channels, not columns
        data = data[..., None]
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"blurlab.io.write: folder {str(folder)!r} does not exist")

    oiio = _oiio()
    channels = data.shape[2]
    spec = oiio.ImageSpec(data.shape[1], data.shape[0], channels, _oiio_type(oiio, data.dtype))
    # Channels are data: OpenImageIO must not (un)premultiply by alpha on the way.
    spec.attribute("oiio:UnassociatedAlpha", 1)
    if channel_names is not None:
        names = [str(n) for n in channel_names]
        if suffix != ".exr" or len(names) != channels or len(set(names)) != channels:
            raise ValueError(
                f"blurlab.io.write: channel_names needs {channels} distinct names and an .exr file"
            )
        spec.channelnames = tuple(names)
        spec.alpha_channel = -1  # no channel is alpha unless named so: nothing is premultiplied
    if suffix == ".png":
        spec.attribute("oiio:ColorSpace", "sRGB")
        spec.attribute("png:compressionLevel", png_compression)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=suffix, dir=folder)
    os.close(fd)
    try:
        out = oiio.ImageOutput.create(tmp_name)
        if out is None:
            raise OSError(
                f"blurlab.io.write: OpenImageIO has no writer for {suffix}: {_error_text(oiio)}"
            )
        if not out.open(tmp_name, spec):
            raise OSError(f"blurlab.io.write: cannot open {path}: {_error_text(out)}")
        ok = out.write_image(data)
        closed = out.close()
        if not (ok and closed):
            raise OSError(f"blurlab.io.write: writing {path} failed: {_error_text(out)}")
        publish(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


def publish(tmp_name: str | os.PathLike, path: str | os.PathLike) -> None:
    """Moves a finished temporary file onto `path` in one step, with the permissions a newly
    created file gets (0666 less the umask: 0644 by default). mkstemp makes its files 0600,
    which a web server or a colleague could not read."""
    mask = os.umask(0o022)  # reading the umask means setting it; put it straight back
    os.umask(mask)
    os.chmod(tmp_name, 0o666 & ~mask)
    os.replace(tmp_name, path)


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Writes `text` to `path` atomically (a temporary file in the same folder, then publish):
    a reader never sees half a file, and an interrupted write leaves the old one."""
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        publish(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


MAX_READ_VALUES = 1 << 28  # numbers in one image read (an 8192 x 8192 RGBA image, 1 GiB)


def read(path: str | os.PathLike) -> np.ndarray:
    """Reads an image: (H, W, C) float32 for float files (EXR), uint8 for 8-bit files (PNG)."""
    return _read(path, "read", keep_uint8=True)[1]


def read_channels(path: str | os.PathLike) -> tuple[list[str], np.ndarray]:
    """A float image's channel names and its pixels as (H, W, C) float32, read whole: every
    subimage of the first one's size, channels in file order. A multi-part EXR (Blender 5
    writes each pass of a multi-layer file as its own part) is one image of all its layers;
    parts of another size are not read."""
    return _read(path, "read_channels", keep_uint8=False, every_part=True)


def image_size(path: str | os.PathLike) -> tuple[int, int]:
    """(width, height) of an image file, from its header: no pixel is read, so a sequence's
    frames can be checked against each other before any is loaded."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"blurlab.io.image_size: no such file: {path}")
    oiio = _oiio()
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise OSError(f"blurlab.io.image_size: cannot read {path}: {_error_text(oiio)}")
    try:
        spec = image.spec()
        return int(spec.width), int(spec.height)
    finally:
        image.close()


def _read(
    path, caller: str, keep_uint8: bool, every_part: bool = False
) -> tuple[list[str], np.ndarray]:
    """Channel names and pixels (of the first subimage, or of every one of its size). Files
    from outside are untrusted: an image of more than MAX_READ_VALUES numbers is refused
    before its pixels are read."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"blurlab.io.{caller}: no such file: {path}")
    oiio = _oiio()
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    image = oiio.ImageInput.open(str(path), config)
    if image is None:
        raise OSError(f"blurlab.io.{caller}: cannot read {path}: {_error_text(oiio)}")
    try:
        spec = image.spec()
        values = spec.width * spec.height * spec.nchannels
        if not 0 < values <= MAX_READ_VALUES:
            raise OSError(
                f"blurlab.io.{caller}: {path} is {spec.width}x{spec.height}x{spec.nchannels}; "
                f"at most {MAX_READ_VALUES} values are read"
            )
        uint8 = keep_uint8 and spec.format.basetype == oiio.UINT8
        names, parts = [], []
        part = 0
        while part == 0 or (every_part and image.seek_subimage(part, 0)):
            here = image.spec()
            part += 1
            if (here.width, here.height) != (spec.width, spec.height):
                continue
            values += 0 if part == 1 else here.width * here.height * here.nchannels
            if values > MAX_READ_VALUES:
                raise OSError(
                    f"blurlab.io.{caller}: {path}'s parts hold more than {MAX_READ_VALUES} "
                    "values, the most that are read"
                )
            pixels = image.read_image(oiio.UINT8 if uint8 else oiio.FLOAT)
            if pixels is None:
                raise OSError(
                    f"blurlab.io.{caller}: {path} is corrupt or truncated: {_error_text(image)}"
                )
            names += list(here.channelnames)
            parts.append(
                np.asarray(pixels, dtype=np.uint8 if uint8 else np.float32).reshape(
                    spec.height, spec.width, here.nchannels
                )
            )
    finally:
        image.close()
    return names, np.concatenate(parts, axis=2)


def _error_text(source) -> str:
    """OpenImageIO's error message; a corrupt file can put bytes that are not UTF-8 in it."""
    try:
        return source.geterror()
    except UnicodeDecodeError as error:
        return error.object.decode("utf-8", "replace")


def _encode(array: np.ndarray, suffix: str) -> np.ndarray:
    if suffix == ".png":
        if array.dtype == np.uint8:
            return np.ascontiguousarray(array)
        return np.ascontiguousarray(srgb8(array))
    if array.dtype == np.uint8:
        return np.ascontiguousarray(array.astype(np.float32) / np.float32(255.0))
    if array.dtype == np.float64:
        return np.ascontiguousarray(array.astype(np.float32))
    return np.ascontiguousarray(array)


def _oiio_type(oiio, dtype: np.dtype):
    return {"uint8": oiio.UINT8, "float16": oiio.HALF, "float32": oiio.FLOAT}[dtype.name]
