"""LDR-FLIP on the GPU (docs/spec.md §6.1): `gpu_flip` and `gpu_flip_map`, two compute passes
whose kernels and constants come from the NumPy twin (blurlab.twins.flip), compiled once per
context and pixels per degree. HDR-FLIP (blurlab.metrics.gpu_hdr_flip, §6.2) runs them once
per exposure.
"""

from __future__ import annotations

import numpy as np

from ..twins import flip as flip_twin
from .reductions import check_same_size


def _glsl_floats(values) -> str:
    return f"float[{len(values)}](" + ", ".join(f"{float(v):.9e}" for v in values) + ")"


def _flip_defines(ppd: float) -> dict:
    """The kernels and constants of LDR-FLIP at `ppd` pixels per degree, computed in double
    (blurlab.twins.flip) and compiled into the shaders (about 1 ms of NumPy: made once per
    context and ppd, with the passes, in _flip_passes)."""
    csf = flip_twin.csf_kernels(ppd)
    g, d, dd = flip_twin.feature_kernels(ppd)
    inverse = flip_twin.XYZ_TO_RGB * flip_twin.WHITE  # undoes RGB_TO_XYZ / white
    return {
        "CSF_RADIUS": csf.shape[-1] // 2,
        "CSF_Y": _glsl_floats(csf[0, 0]),
        "CSF_CX": _glsl_floats(csf[1, 0]),
        "CSF_CZ1": _glsl_floats(csf[2, 0]),
        "CSF_CZ2": _glsl_floats(csf[2, 1]),
        "FEATURE_RADIUS": len(g) // 2,
        "FEATURE_G": _glsl_floats(g),
        "FEATURE_D": _glsl_floats(d),
        "FEATURE_DD": _glsl_floats(dd),
        # mat3 takes columns.
        "XYZ_TO_RGB_NORMALIZED": "mat3(" + ", ".join(f"{v:.9e}" for v in inverse.T.ravel()) + ")",
        "CMAX": f"{flip_twin.max_color_distance():.9e}",
    }


def _check_ppd(ppd) -> float:
    if isinstance(ppd, bool) or not isinstance(ppd, (int, float)) or not 1.0 <= ppd <= 1000.0:
        raise ValueError(
            f"blurlab.metrics.gpu_flip: ppd (pixels per degree) must be a number in "
            f"[1, 1000], not {ppd!r}"
        )
    return float(ppd)


def _flip_passes(ctx, ppd: float):
    """LDR-FLIP's two passes at `ppd`, compiled once per context and ppd."""

    def make():
        defines = _flip_defines(ppd)
        return (
            ctx.shader_pass("passes/flip_horizontal.comp", defines),
            ctx.shader_pass("passes/flip_error.comp", defines),
        )

    return ctx.cached(("gpu_flip", ppd), make)


def flip_textures(ctx, reference, test, ppd):
    """Runs LDR-FLIP's two passes; returns the (H, W) error map and the per-group partial sums
    as pooled textures (the caller recycles them)."""
    check_same_size(reference, test, "gpu_flip")
    if reference.channels < 3 or test.channels < 3:
        raise ValueError("blurlab.metrics.gpu_flip: the images need RGB channels")
    horizontal, vertical = _flip_passes(ctx, _check_ppd(ppd))
    height, width = reference.shape[:2]
    rows = [ctx.pooled((height, width, 4)) for _ in range(4)]
    names = ("reference_color", "reference_features", "test_color", "test_features")
    horizontal.run({"reference": reference, "test": test}, dict(zip(names, rows, strict=True)))
    error = ctx.pooled((height, width))
    partials = ctx.pooled((-(-height // 16), -(-width // 16)))
    vertical.run(dict(zip(names, rows, strict=True)), {"error": error, "partials": partials})
    ctx.recycle(*rows)
    return error, partials


def gpu_flip(ctx, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> float:
    """Mean LDR-FLIP error (Andersson et al. 2020; docs/spec.md §6.1) of two (H, W, 4) float32
    textures of linear colour, computed on the GPU: the `flip` of the images, as flip-evaluator
    computes it (tests/test_flip_gpu.py), with only one partial sum per 16 x 16 pixels read
    back. `ppd`: pixels per degree of visual angle (flip-evaluator's default: 67.02). NaN
    colour reads as 0 and infinities clip to [0, 1], as every pass reads colour."""
    error, partials = flip_textures(ctx, reference, test, ppd)
    ctx.recycle(error)
    return flip_mean(ctx, partials, reference.shape)


def flip_mean(ctx, partials, shape) -> float:
    """The mean FLIP error from its per-group partial sums, which go back to the pool."""
    total = float(np.sum(partials.download(), dtype=np.float64))
    ctx.recycle(partials)
    return total / (shape[0] * shape[1])


def gpu_flip_map(ctx, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> np.ndarray:
    """The (H, W) per-pixel LDR-FLIP error of `gpu_flip`, in [0, 1]."""
    error, partials = flip_textures(ctx, reference, test, ppd)
    image = error.download()
    ctx.recycle(error, partials)
    return image
