"""Error against a reference, docs/spec.md §6: each metric is registered once (`Metric`:
its direction, range, HDR or LDR, NumPy and GPU implementations), and sweeps, the study,
charts, `recommend` and docs/metrics.md read the registry: `registered()` lists the names,
`get(name)` gives one. docs/adding_a_metric.md adds one.

The modules, by concern: `registry`; `ldr`, the LDR metrics in NumPy (PSNR, SSIM, FLIP on
linear colour clipped to [0, 1], error maps, flicker, tile-border error); `reductions`, the
squared error and SSIM reduced on the GPU (`gpu_mse`, `gpu_ssim`, `gpu_mse_ssim`,
`prepare_reference`); `flip_gpu`, LDR-FLIP on the GPU (`gpu_flip`); `queue`, GPU metrics
issued now and read later (`MetricQueue`, `MetricBatches`, docs/spec.md §6.3); `hdr`, the
unclipped metrics of HDR scenes (docs/spec.md §6.2: `hdr_flip` and `gpu_hdr_flip`, `psnr_tm`,
`ssim_tm`, `log_luminance_error`, `energy_ratio`, `hdr_scores`); `temporal`, metrics of sequences
(docs/spec.md §21.3: `temporal_instability`, `per_frame`); `perceptual`, ColorVideoVDP and
FovVideoVDP on sequences where the optional extra `blurlab[perceptual]` is installed.
"""

# The import order is the registry's: the order of the metrics' columns in sweep tables.
# isort: off
from .registry import (
    Metric,
    REDUCTIONS,
    REFERENCES,
    check_names,
    cpu_scores,
    default_names,
    gpu_scores,
)
from .registry import get, reference_page, register, registered, unregister
from .reductions import (
    PREPARED_SSIM_LAYOUT,
    SSIM_LAYOUT,
    SSIM_LAYOUTS,
    PreparedReference,
    gpu_mse,
    gpu_mse_ssim,
    gpu_ssim,
    prepare_reference,
)
from .flip_gpu import gpu_flip, gpu_flip_map
from .queue import MetricBatches, MetricQueue, issue_reductions, reduced_values
from .ldr import (
    LUMINANCE,
    error_map,
    flicker,
    flip,
    gpu_psnr,
    mse,
    psnr,
    psnr_from_mse,
    ssim,
    tile_border_error,
)
from .hdr import (
    ACES,
    FLIP_TARGET,
    HDR_METRICS,
    KEY,
    LOG_DELTA,
    energy_ratio,
    exposure,
    flip_exposure_range,
    hdr_flip_exposures,
    gpu_hdr_flip,
    hdr_flip,
    hdr_scores,
    log_luminance_error,
    luminance,
    psnr_tm,
    ssim_tm,
    tone_map,
)
from .temporal import gpu_pair_instability, per_frame, temporal_instability
from . import perceptual  # noqa: F401  (registers colorvideovdp and fovvideovdp where installed)

# isort: on

__all__ = [
    "reduced_values",
    "issue_reductions",
    "default_names",
    "cpu_scores",
    "gpu_scores",
    "check_names",
    "ACES",
    "FLIP_TARGET",
    "HDR_METRICS",
    "KEY",
    "LOG_DELTA",
    "LUMINANCE",
    "PREPARED_SSIM_LAYOUT",
    "REDUCTIONS",
    "REFERENCES",
    "SSIM_LAYOUT",
    "SSIM_LAYOUTS",
    "Metric",
    "MetricBatches",
    "MetricQueue",
    "PreparedReference",
    "energy_ratio",
    "error_map",
    "exposure",
    "flicker",
    "flip",
    "flip_exposure_range",
    "hdr_flip_exposures",
    "get",
    "gpu_flip",
    "gpu_hdr_flip",
    "gpu_flip_map",
    "gpu_mse",
    "gpu_pair_instability",
    "gpu_mse_ssim",
    "gpu_psnr",
    "gpu_ssim",
    "hdr_flip",
    "hdr_scores",
    "log_luminance_error",
    "luminance",
    "mse",
    "prepare_reference",
    "psnr",
    "psnr_from_mse",
    "psnr_tm",
    "reference_page",
    "register",
    "registered",
    "ssim",
    "ssim_tm",
    "tile_border_error",
    "tone_map",
    "unregister",
    "per_frame",
    "temporal_instability",
]
