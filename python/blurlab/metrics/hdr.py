"""The HDR metrics in NumPy (docs/spec.md §6.2), for scenes lit far above 1: nothing is clipped
above 1. `hdr_flip`, `psnr_tm` and `ssim_tm` (after `tone_map` at the reference's `exposure`),
`log_luminance_error` and `energy_ratio`, each registered here; `hdr_scores` computes several
of them with the exposure they used.
"""

from __future__ import annotations

import math

import numpy as np

from ..io.images import linear_to_srgb
from ..twins import flip as flip_twin
from .flip_gpu import flip_mean, flip_textures
from .ldr import LUMINANCE, check_same_shape, psnr, rgb, ssim
from .reductions import check_same_size
from .registry import Metric, get, register, registered

# Reinhard et al. 2002, eq. 1: the log-average luminance uses δ against log(0), and the key
# 0.18 maps it to middle grey.
KEY = 0.18
LOG_DELTA = 1e-4
# The ACES fit (Narkowicz 2016) that HDR-FLIP assumes, with FLIP's pre-exposure 0.6 folded
# into the coefficients: t(x) = (a x² + b x) / (c x² + d x + e).
ACES = (0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14)
FLIP_TARGET = 0.85  # HDR-FLIP's exposure range brings Y_max, then the median Y, to t = 0.85


def _hdr_rgb(image, what: str = "image") -> np.ndarray:
    """RGB of an (H, W, 3|4) linear image as float64, unclipped; refuses NaN and inf."""
    values = rgb(image)
    if not np.isfinite(values).all():
        raise ValueError(
            f"blurlab.metrics: the {what} has NaN or inf values; HDR metrics need finite colour"
        )
    return values


def _hdr_pair(reference, test) -> tuple[np.ndarray, np.ndarray]:
    a, b = _hdr_rgb(reference, "reference"), _hdr_rgb(test, "test image")
    check_same_shape(a, b)
    return a, b


def luminance(image) -> np.ndarray:
    """(H, W) Rec. 709 luminance of linear RGB, unclipped."""
    return _hdr_rgb(image) @ LUMINANCE


def exposure(reference) -> float:
    """The exposure that maps the reference's log-average luminance to middle grey
    (Reinhard et al. 2002): KEY / exp(mean(log(δ + max(Y, 0)))); the one exposure of
    `tone_map`, `psnr_tm`, `ssim_tm` and the report's pictures."""
    y = np.maximum(luminance(reference), 0.0)
    return float(KEY / np.exp(np.mean(np.log(LOG_DELTA + y))))


def _check_exposure(value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"blurlab.metrics: exposure must be a number, not {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"blurlab.metrics: exposure must be finite and > 0, not {value}")
    return float(value)


def tone_map(image, exposure: float) -> np.ndarray:
    """(H, W, 3) display values in [0, 1]: Reinhard's x / (1 + x) per channel on
    x = exposure · max(rgb, 0), then the sRGB transfer function (docs/spec.md §6.2). Never
    clips a highlight to a constant: a brighter input always maps to a brighter output."""
    x = _check_exposure(exposure) * np.maximum(_hdr_rgb(image), 0.0)
    return linear_to_srgb(x / (1.0 + x))


def _tone_mapped_pair(reference, test, exposure_value):
    a, b = _hdr_pair(reference, test)
    e = exposure(a) if exposure_value is None else exposure_value
    return tone_map(a, e), tone_map(b, e)


def psnr_tm(reference, test, exposure: float | None = None) -> float:
    """PSNR (dB, peak 1) of the two images tone-mapped alike (`tone_map`, the reference's
    exposure unless one is given)."""
    return psnr(*_tone_mapped_pair(reference, test, exposure))


def ssim_tm(reference, test, exposure: float | None = None) -> float:
    """`ssim` of the luma (Rec. 709 weights on the sRGB-encoded values) of the two images
    tone-mapped alike (`tone_map`, the reference's exposure unless one is given)."""
    return ssim(*_tone_mapped_pair(reference, test, exposure))


def log_luminance_error(reference, test) -> float:
    """Mean |log2((δ + Y_test) / (δ + Y_ref))| over pixels: the error in stops, negative
    luminance taken as 0, δ = LOG_DELTA."""
    a, b = _hdr_pair(reference, test)
    ya, yb = np.maximum(a @ LUMINANCE, 0.0), np.maximum(b @ LUMINANCE, 0.0)
    return float(np.mean(np.abs(np.log2((LOG_DELTA + yb) / (LOG_DELTA + ya)))))


def energy_ratio(reference, test) -> float:
    """Σ test / Σ reference over pixels and RGB: 1 when the output keeps the reference's total
    radiance, < 1 when it loses light, > 1 when it adds some (+inf if the reference is black
    and the output is not)."""
    a, b = _hdr_pair(reference, test)
    total_a, total_b = float(a.sum()), float(b.sum())
    if total_a <= 0:
        return 1.0 if total_b == total_a else math.inf
    return total_b / total_a


def flip_exposure_range(reference) -> tuple[float, float]:
    """HDR-FLIP's exposure range (Andersson et al. 2021) from the reference, in stops: the
    start exposure brings the largest luminance, the stop exposure the median luminance (of
    the pixels with Y > 0, so that a mostly black image has a range), to FLIP_TARGET under
    the ACES curve."""
    y = np.maximum(luminance(reference), 0.0)
    lit = y[y > 0]
    if lit.size == 0:
        return 0.0, 0.0
    a, b, c, d, e = ACES
    t = FLIP_TARGET  # solve t(x) = t: (a - t c) x² + (b - t d) x - t e = 0, the positive root
    qa, qb, qc = a - t * c, b - t * d, -t * e
    x = (-qb + math.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
    start, stop = math.log2(x / float(lit.max())), math.log2(x / float(np.median(lit)))
    return start, stop


def hdr_flip(reference, test) -> float:
    """Mean HDR-FLIP error (flip-evaluator's "HDR" mode, ACES tone mapper), 0 = identical;
    its exposure range is `flip_exposure_range(reference)`. Negative values count as 0."""
    import flip_evaluator

    a, b = _hdr_pair(reference, test)
    start, stop = flip_exposure_range(a)
    linear = lambda c: np.ascontiguousarray(np.maximum(c, 0.0), dtype=np.float32)  # noqa: E731
    _, mean, _ = flip_evaluator.evaluate(
        linear(a),
        linear(b),
        "HDR",
        inputsRGB=False,
        applyMagma=False,
        parameters={"startExposure": start, "stopExposure": stop, "tonemapper": "ACES"},
    )
    return float(mean)


def hdr_flip_exposures(start: float, stop: float) -> list[float]:
    """HDR-FLIP's exposures in stops, as flip-evaluator takes them when it is given only the
    range: max(2, ceil(stop - start)) of them, evenly spaced from start to stop."""
    count = max(2, math.ceil(stop - start))
    step = (stop - start) / (count - 1)
    return [start + i * step for i in range(count)]


def _hdr_flip_passes(ctx):
    """HDR-FLIP's tone-mapping pass and its running maximum, compiled once per context."""
    return ctx.cached(
        ("gpu_hdr_flip",),
        lambda: (
            ctx.shader_pass("passes/hdr_flip_tonemap.comp"),
            ctx.shader_pass("passes/hdr_flip_worst.comp"),
        ),
    )


def gpu_hdr_flip(
    ctx, reference, test, ppd: float = flip_twin.DEFAULT_PPD, exposure_range=None
) -> float:
    """Mean HDR-FLIP error (Andersson et al. 2021; docs/spec.md §6.2) of two (H, W, 4) float32
    textures of linear HDR colour, computed on the GPU: at each exposure of
    `hdr_flip_exposures(*exposure_range)` both images are tone-mapped by the ACES fit, LDR-FLIP
    compares them, and each pixel keeps its largest error. `exposure_range`: (start, stop) in
    stops, by default blurlab.metrics.flip_exposure_range of the reference (which reads the
    reference back; a caller that holds it on the host passes the range instead). Matches
    flip-evaluator's "HDR" mode (tests/test_flip_gpu.py)."""
    check_same_size(reference, test, "gpu_hdr_flip")
    if reference.channels < 3 or test.channels < 3:
        raise ValueError("blurlab.metrics.gpu_hdr_flip: the images need RGB channels")
    if exposure_range is None:
        exposure_range = flip_exposure_range(reference.download())
    start, stop = (float(v) for v in exposure_range)
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise ValueError(
            f"blurlab.metrics.gpu_hdr_flip: the exposure range must be finite, not {exposure_range}"
        )
    tonemap, keep_worst = _hdr_flip_passes(ctx)
    height, width = reference.shape[:2]
    ldr = [ctx.pooled((height, width, 4)) for _ in range(2)]
    worst = ctx.pooled((height, width))
    partials = None
    k0, k1, k3, k4, k5 = ACES
    for i, exposure in enumerate(hdr_flip_exposures(start, stop)):
        tonemap.run(
            {"reference": reference, "test": test},
            {"reference_ldr": ldr[0], "test_ldr": ldr[1]},
            {
                "exposure_scale": 2.0**exposure,
                "numerator": (k0, k1, 0.0),
                "denominator": (k3, k4, k5),
            },
        )
        error, exposure_partials = flip_textures(ctx, ldr[0], ldr[1], ppd)
        if partials is None:
            partials = exposure_partials
        else:
            ctx.recycle(exposure_partials)
        keep_worst.run(
            {"error": error}, {"worst": worst, "partials": partials}, {"first": int(i == 0)}
        )
        ctx.recycle(error)
    ctx.recycle(*ldr, worst)
    return flip_mean(ctx, partials, reference.shape)


def _register_hdr(name: str, function, doc: str, label: str, higher_is_better, **more) -> None:
    register(
        Metric(
            name=name,
            doc=doc,
            spec="§6.2",
            higher_is_better=higher_is_better,
            numpy=function,
            label=label,
            hdr=True,
            default=True,
            **more,
        )
    )


_register_hdr(
    "psnr_tm",
    psnr_tm,
    "PSNR (peak 1) of the reference and the test image tone-mapped alike: Reinhard's x / (1 + x) "
    "per channel of the colour times the reference's exposure, then sRGB.",
    "PSNR after tone mapping",
    True,
    range=(0.0, math.inf),
    unit="dB",
)
_register_hdr(
    "ssim_tm",
    ssim_tm,
    "SSIM (the window and constants of `ssim`) of the luma of the two images tone-mapped alike, "
    "at the reference's exposure.",
    "SSIM after tone mapping",
    True,
    range=(-1.0, 1.0),
)
_register_hdr(
    "hdr_flip",
    hdr_flip,
    "Mean HDR-FLIP error (Andersson et al. 2021; flip-evaluator's ACES tone mapper), its "
    "exposure range from the reference's largest and median luminance; 0 for identical images.",
    "HDR-FLIP",
    False,
    range=(0.0, 1.0),
    gpu=gpu_hdr_flip,
    gpu_arguments=lambda reference: {"exposure_range": flip_exposure_range(reference)},
    tolerance=1e-4,
)
_register_hdr(
    "log_lum_error",
    log_luminance_error,
    "Mean over pixels of |log2((δ + Y_test) / (δ + Y_reference))|, negative luminance taken as "
    "0, δ = 1e-4: the luminance error in stops.",
    "log2-luminance error",
    False,
    range=(0.0, math.inf),
    unit="stops",
)
_register_hdr(
    "energy_ratio",
    energy_ratio,
    "Σ test / Σ reference over pixels and RGB: 1 keeps the reference's total radiance, < 1 lost "
    "light, > 1 added some (+inf for a black reference and a test that is not).",
    "energy ratio",
    None,
    range=(0.0, math.inf),
    best=1.0,
)

# The HDR metrics' NumPy implementations by name, each f(reference, test).
HDR_METRICS = {name: get(name).numpy for name in registered() if get(name).hdr}


def hdr_scores(reference, test, names=None) -> dict[str, float]:
    """{name: value} of the HDR metrics `names` (default: every registered HDR metric) of
    `test` against `reference`, and "exposure", the one `psnr_tm` and `ssim_tm` used."""
    hdr = [n for n in registered() if get(n).hdr]
    names = hdr if names is None else list(names)
    unknown = [n for n in names if n not in hdr]
    if unknown:
        raise ValueError(f"blurlab.metrics: unknown HDR metrics {unknown}; choose from {hdr}")
    a, b = _hdr_pair(reference, test)
    return {**{name: get(name).numpy(a, b) for name in names}, "exposure": exposure(a)}
