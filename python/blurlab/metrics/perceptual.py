"""A model of human vision over time (docs/spec.md §21.3): FovVideoVDP, a video difference
metric calibrated on human judgements of video quality, in just-objectionable-difference units
(JOD: 10 is no visible difference; one JOD less is preferred by 75 % of observers).

It comes with the optional extra `blurlab[perceptual]` (pyfvvdp with PyTorch on the CPU). Its
calibration and display models ship inside the package: nothing is downloaded when it runs.
Where it is not installed the metric is not registered, and asking for it by name says what
to install. (ColorVideoVDP, its successor, needs torchvision, whose only wheels on PyPI are
built against CUDA PyTorch and fail to load beside the CPU one: docs/temporal.md.)
"""

from __future__ import annotations

import functools
import importlib.util
import logging

import numpy as np

from ..io import images as io
from .registry import Metric, declare_optional, register
from .temporal import check_sequence

NAME = "fovvideovdp"
INSTALL = "pip install 'blurlab[perceptual]'"  # pyfvvdp and PyTorch
# The display the frames are judged on: pyfvvdp's 24-inch 1920 x 1080 monitor of 200 cd/m² in
# office light, seen from 60 cm, each frame pixel one display pixel, not foveated.
DISPLAY = "standard_fhd"
# The frame rate a registered sequence metric assumes: bl.sequence's default.
DEFAULT_FPS = 60.0


def available() -> bool:
    """Whether pyfvvdp and PyTorch are installed."""
    return all(importlib.util.find_spec(m) is not None for m in ("torch", "pyfvvdp"))


@functools.cache
def _model(display: str):
    import pyfvvdp  # the optional extra: imported on first use (PyTorch takes seconds)
    import torch

    # pyfvvdp logs a warning per frame for values outside [0, 1]; the frames are clipped here.
    logging.getLogger("pyfvvdp").setLevel(logging.ERROR)
    return pyfvvdp.fvvdp(
        display_name=display, heatmap=None, foveated=False, quiet=True, device=torch.device("cpu")
    )


def fovvideovdp(reference, test, fps: float = DEFAULT_FPS, display: str = DISPLAY) -> float:
    """FovVideoVDP's quality in JOD of sequence `test` against `reference` (both (N >= 2, H, W,
    3|4) linear colour, clipped to [0, 1] and sRGB-encoded as the display shows them) at `fps`
    frames per second on pyfvvdp's display model `display`. Higher is better; 10: no visible
    difference."""
    if not available():
        raise ImportError(f"blurlab.metrics.{NAME} needs FovVideoVDP: {INSTALL}")
    reference, test = check_sequence(reference, "reference"), check_sequence(test, "test")
    if reference.shape[:3] != test.shape[:3]:
        raise ValueError(
            f"blurlab.metrics: sequences differ in shape: {reference.shape} and {test.shape}"
        )
    if not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
        raise ValueError(f"blurlab.metrics.{NAME}: fps must be a finite number > 0, not {fps!r}")

    def shown(frames):
        return np.ascontiguousarray(io.linear_to_srgb(frames[..., :3]), np.float32)

    quality, _ = _model(display).predict(
        shown(test), shown(reference), dim_order="FHWC", frames_per_second=float(fps)
    )
    return float(quality)


DOC = (
    "FovVideoVDP (Mantiuk et al. 2021), a video difference metric calibrated on human "
    "judgements, in JOD (10: no visible difference), of sequences clipped and sRGB-encoded on a "
    f"1920 x 1080 monitor of 200 cd/m² at {DEFAULT_FPS:g} frames per second (docs/spec.md §21.3)."
)
LABEL = "FovVideoVDP"
declare_optional(NAME, LABEL, DOC, INSTALL)
if available():
    register(
        Metric(
            name=NAME,
            doc=DOC,
            spec="§21.3",
            higher_is_better=True,
            range=(-np.inf, 10.0),
            reference="antialiased",
            numpy=fovvideovdp,
            label=LABEL,
            unit="JOD",
            sequence=True,
        )
    )
