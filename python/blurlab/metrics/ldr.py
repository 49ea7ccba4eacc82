"""The LDR metrics in NumPy (docs/spec.md §6): PSNR (linear colour clipped to [0, 1]), SSIM on
luminance, FLIP (the flip-evaluator package, on sRGB), per-pixel error maps, flicker of
sequences and the tile-border error. They clip to [0, 1] on purpose: they measure what an LDR
display shows of linear colour (the HDR metrics are in blurlab.metrics.hdr). PSNR, SSIM, FLIP
and PSNR against the antialiased reference are registered here, with their GPU twins.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..io.images import linear_to_srgb
from .flip_gpu import gpu_flip
from .reductions import gpu_mse, gpu_ssim
from .registry import Metric, register

# Rec. 709 / sRGB luminance weights, for SSIM on luminance.
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def rgb(image, dtype=np.float64) -> np.ndarray:
    """The RGB channels of an (H, W, 3|4) image as `dtype`, unclipped."""
    image = np.asarray(image, dtype)
    if image.ndim != 3 or image.shape[2] < 3:
        raise ValueError(f"blurlab.metrics: expected an (H, W, 3 or 4) image, not {image.shape}")
    return image[..., :3]


def check_same_shape(a: np.ndarray, b: np.ndarray) -> None:
    if a.shape != b.shape:
        raise ValueError(f"blurlab.metrics: images differ in shape: {a.shape} and {b.shape}")


def _pair(a, b, dtype=np.float64) -> tuple[np.ndarray, np.ndarray]:
    """Both images' RGB clipped to [0, 1]: what an LDR display shows of linear colour."""
    a, b = np.clip(rgb(a, dtype), 0.0, 1.0), np.clip(rgb(b, dtype), 0.0, 1.0)
    check_same_shape(a, b)
    return a, b


def mse(a, b) -> float:
    """Mean squared error over pixels and RGB, colors clipped to [0, 1]."""
    a, b = _pair(a, b)
    return float(np.mean((a - b) ** 2))


def psnr_from_mse(value: float) -> float:
    """PSNR in dB for a peak of 1; identical images give +inf."""
    return math.inf if value <= 0 else 10.0 * math.log10(1.0 / value)


def psnr(a, b) -> float:
    """PSNR in dB of linear color clipped to [0, 1] (docs/spec.md §6)."""
    return psnr_from_mse(mse(a, b))


def gaussian_blur(image: np.ndarray, sigma: float = 1.5, radius: int = 5) -> np.ndarray:
    # np.pad's reflect mirrors without repeating the edge, and repeats the mirror for images
    # smaller than the window (period 2(n - 1)); shaders/passes/ssim.comp does the same.
    x = np.arange(-radius, radius + 1)
    kernel = np.exp(-(x**2) / (2 * sigma**2))
    kernel /= kernel.sum()
    padded = np.pad(image, radius, mode="reflect")
    rows = sum(w * padded[:, i : i + image.shape[1]] for i, w in enumerate(kernel))
    return sum(w * rows[i : i + image.shape[0], :] for i, w in enumerate(kernel))


def ssim(a, b) -> float:
    """Mean SSIM (Wang et al. 2004) of the luminance, Gaussian window σ = 1.5, 11 taps,
    C1 = (0.01)², C2 = (0.03)² for a data range of 1."""
    a, b = _pair(a, b)
    x, y = a @ LUMINANCE, b @ LUMINANCE
    c1, c2 = 0.01**2, 0.03**2
    mx, my = gaussian_blur(x), gaussian_blur(y)
    sxx = gaussian_blur(x * x) - mx * mx
    syy = gaussian_blur(y * y) - my * my
    sxy = gaussian_blur(x * y) - mx * my
    s = ((2 * mx * my + c1) * (2 * sxy + c2)) / ((mx * mx + my * my + c1) * (sxx + syy + c2))
    return float(np.mean(s))


def flip(reference, test) -> float:
    """Mean FLIP error (Andersson et al. 2020) of the sRGB-encoded images, 0 = identical."""
    import flip_evaluator

    ref, out = _pair(reference, test)
    srgb = lambda c: np.ascontiguousarray(linear_to_srgb(c), dtype=np.float32)  # noqa: E731
    _, mean, _ = flip_evaluator.evaluate(
        srgb(ref), srgb(out), "LDR", inputsRGB=True, applyMagma=False
    )
    return float(mean)


def error_map(a, b) -> np.ndarray:
    """(H, W) float32 per-pixel mean absolute RGB error, colors clipped to [0, 1]. In float32:
    it is drawn and searched for its worst windows, never summed over an image, and float64
    took 4x as long on the study's 1080p pictures."""
    a, b = _pair(a, b, np.float32)
    a -= b
    np.abs(a, out=a)
    return a.sum(axis=-1) / np.float32(3.0)


def flicker(frames, still) -> float:
    """Mean |out_n - out_{n-1}| over RGB on the pixels where `still` is true (docs/spec.md §6)."""
    frames = np.asarray(frames, np.float64)
    if frames.ndim != 4 or len(frames) < 2:
        raise ValueError("blurlab.metrics.flicker: needs a (N >= 2, H, W, C) sequence")
    still = np.asarray(still, bool)
    if still.shape != frames.shape[1:3] or not still.any():
        raise ValueError("blurlab.metrics.flicker: `still` must be an (H, W) mask with pixels")
    steps = np.abs(np.diff(frames[..., :3], axis=0)).mean(axis=-1)
    return float(steps[:, still].mean())


def tile_border_error(reference, test, k: int, band: int = 1) -> dict:
    """Blockiness of a tiled filter (the Urho3D thesis saw it at k = 32), two ways:

    - level: the mean per-pixel error (`error_map`) on pixels within `band` pixels of a k x k
      tile border ("border") and on the pixels inside the tiles ("interior");
    - seams: the mean jump of the signed error (test - reference, mean over RGB) between
      neighboring pixels on either side of a tile border ("border_step") and between the other
      neighboring pixels ("interior_step").

    "ratio" and "step_ratio" are border / interior (> 1: errors line up with the tile grid).
    Borders are the lines x = i·k and y = i·k between tiles; the image edges are not borders."""
    if isinstance(k, bool) or not isinstance(k, int) or k < 2:
        raise ValueError(f"blurlab.metrics.tile_border_error: k must be an integer >= 2, not {k!r}")
    if isinstance(band, bool) or not isinstance(band, int) or not 1 <= band <= k // 2:
        raise ValueError(
            f"blurlab.metrics.tile_border_error: band must be an integer in 1..k/2, not {band!r}"
        )
    a, b = _pair(reference, test)
    errors = np.mean(np.abs(a - b), axis=-1)
    signed = np.mean(b - a, axis=-1)
    h, w = errors.shape
    if h <= k and w <= k:
        raise ValueError(
            f"blurlab.metrics.tile_border_error: a {w}x{h} image has no tile border at k = {k}"
        )

    def near_border(n: int) -> np.ndarray:
        near = np.zeros(n, bool)
        for border in range(k, n, k):  # the border between pixels border - 1 and border
            near[border - band : border + band] = True
        return near

    border = near_border(h)[:, None] | near_border(w)[None, :]
    # Jumps between horizontal neighbors (x, x + 1) and vertical ones (y, y + 1).
    steps_x = np.abs(np.diff(signed, axis=1))
    steps_y = np.abs(np.diff(signed, axis=0))
    across_x = np.broadcast_to((np.arange(1, w) % k == 0)[None, :], steps_x.shape)
    across_y = np.broadcast_to((np.arange(1, h) % k == 0)[:, None], steps_y.shape)
    on_steps = np.concatenate([steps_x[across_x], steps_y[across_y]])
    off_steps = np.concatenate([steps_x[~across_x], steps_y[~across_y]])

    def ratio(on: float, off: float) -> float:
        return on / off if off > 0 else (math.inf if on > 0 else 1.0)

    level_on, level_off = float(errors[border].mean()), float(errors[~border].mean())
    step_on, step_off = float(on_steps.mean()), float(off_steps.mean())
    return {
        "border": level_on,
        "interior": level_off,
        "ratio": ratio(level_on, level_off),
        "border_step": step_on,
        "interior_step": step_off,
        "step_ratio": ratio(step_on, step_off),
        "border_pixels": int(border.sum()),
    }


def gpu_psnr(ctx, reference, test) -> float:
    """`psnr` of two (H, W, 4) float32 textures, from `gpu_mse`'s squared error reduced on the
    GPU."""
    return psnr_from_mse(gpu_mse(ctx, reference, test))


PSNR = register(
    Metric(
        name="psnr",
        doc="Peak signal-to-noise ratio of linear RGB clipped to [0, 1]: 10·log10(1 / MSE) dB, "
        "MSE the mean squared difference over pixels and the three channels; +inf for identical "
        "images.",
        spec="§6",
        higher_is_better=True,
        range=(0.0, math.inf),
        numpy=psnr,
        label="PSNR",
        unit="dB",
        gpu=gpu_psnr,
        reduction="squared_error",
        from_reduction=psnr_from_mse,
        tolerance=1e-3,
        default=True,
    )
)
register(
    Metric(
        name="ssim",
        doc="Mean SSIM (Wang et al. 2004) of the Rec. 709 luminance of linear RGB clipped to "
        "[0, 1]: Gaussian window σ = 1.5 (11 taps), borders mirrored, C1 = 0.01², C2 = 0.03².",
        spec="§6",
        higher_is_better=True,
        range=(-1.0, 1.0),
        numpy=ssim,
        label="SSIM",
        gpu=gpu_ssim,
        reduction="ssim",
        tolerance=1e-5,
        default=True,
    )
)
register(
    Metric(
        name="flip",
        doc="Mean LDR-FLIP error (Andersson et al. 2020) of the sRGB-encoded images, linear RGB "
        "clipped to [0, 1], at 67.02 pixels per degree; 0 for identical images.",
        spec="§6.1",
        higher_is_better=False,
        range=(0.0, 1.0),
        numpy=flip,
        label="FLIP",
        gpu=gpu_flip,
        reduction="flip",
        tolerance=1e-4,
        default=True,
    )
)
# The same PSNR against the other reference (docs/spec.md §11 "Which reference, for what").
register(
    dataclasses.replace(
        PSNR,
        name="psnr_aa",
        doc="PSNR as `psnr` defines it, against the antialiased reference: sub-pixel "
        "positions jittered as well as times, what a path tracer converges to. It also counts "
        "the aliasing of still edges, so it is lower and flatter than `psnr`.",
        spec="§11",
        label="PSNR against the antialiased reference",
        reference="antialiased",
    )
)
