"""Models of human vision over time (docs/spec.md §21.3): ColorVideoVDP and FovVideoVDP, video
difference metrics calibrated on human judgements of video quality, in just-objectionable-
difference units (JOD: 10 is no visible difference; one JOD less is preferred by 75 % of
observers). ColorVideoVDP, FovVideoVDP's successor from the same group, models colour vision
as well as the achromatic contrast FovVideoVDP sees.

Both come with the optional extra `blurlab[perceptual]` (cvvdp and pyfvvdp, with PyTorch and
torchvision; they run on the CPU). Their calibration and display models ship inside the
packages: nothing is downloaded when they run (ColorVideoVDP's learned variants, which fetch
their weights, are not used). Where a model is not installed its metric is not registered, and
asking for it by name says what to install. Both see the frames through one function (`judge`):
clipped to [0, 1], sRGB-encoded, on their package's model of the same 24-inch 1920 × 1080
monitor.
"""

from __future__ import annotations

import functools
import importlib
import importlib.util
import logging
import os
import sys
from dataclasses import dataclass, field

import numpy as np

from ..io import images as io
from .registry import Metric, declare_optional, register
from .temporal import check_sequence

INSTALL = "pip install 'blurlab[perceptual]'"  # cvvdp, pyfvvdp, PyTorch and torchvision
# The display the frames are judged on: each package's 24-inch 1920 x 1080 monitor of
# 200 cd/m² in office light, seen from 60 cm, each frame pixel one display pixel.
DISPLAY = "standard_fhd"
# The frame rate a registered sequence metric assumes: bl.sequence's default.
DEFAULT_FPS = 60.0


@dataclass(frozen=True)
class Model:
    """A model of vision of the extra: its metric's name and label, what it is (for the
    metric's doc), the package and class that build it, the arguments it takes beyond the
    display, the device and the quiet flags, and the modules it needs."""

    name: str
    label: str
    what: str
    package: str
    builder: str
    modules: tuple[str, ...]
    options: dict = field(default_factory=dict)

    @property
    def doc(self) -> str:
        return (
            f"{self.what} calibrated on human judgements, in JOD (10: no visible difference), "
            "of sequences clipped and sRGB-encoded on a 1920 x 1080 monitor of 200 cd/m² at "
            f"{DEFAULT_FPS:g} frames per second (docs/spec.md §21.3)."
        )


MODELS = {
    model.name: model
    for model in (
        Model(
            "colorvideovdp",
            "ColorVideoVDP",
            "ColorVideoVDP (Mantiuk et al. 2024), a colour video difference metric",
            "pycvvdp",
            "cvvdp",
            ("torch", "torchvision", "pycvvdp"),
        ),
        Model(
            "fovvideovdp",
            "FovVideoVDP",
            "FovVideoVDP (Mantiuk et al. 2021), a video difference metric",
            "pyfvvdp",
            "fvvdp",
            ("torch", "pyfvvdp"),
            {"foveated": False},
        ),
    )
}


def model(name: str) -> Model:
    """The model of vision `name` (one of MODELS), or a ValueError naming them."""
    if name not in MODELS:
        raise ValueError(f"blurlab.metrics.perceptual: no model {name!r}; one of {list(MODELS)}")
    return MODELS[name]


def available(name: str | None = None) -> bool:
    """Whether model `name`'s packages are installed (None: every model of the extra's)."""
    names = list(MODELS) if name is None else [model(name).name]
    return all(
        importlib.util.find_spec(module) is not None for n in names for module in MODELS[n].modules
    )


def _import_triton_apart() -> None:
    """PyPI's default torch (the CUDA build) brings triton, which torchvision imports through
    torch._dynamo. triton carries an LLVM of its own: imported into a process where llvmpipe
    (a software Context) has loaded the system's libLLVM, it binds to that library's symbols and
    the interpreter crashes. Imported with RTLD_DEEPBIND it binds to its own first. Nothing is
    done where triton is imported already, absent, or no libLLVM is loaded."""
    if "triton" in sys.modules or not hasattr(os, "RTLD_DEEPBIND"):
        return
    if importlib.util.find_spec("triton") is None:
        return
    try:
        with open("/proc/self/maps") as maps:
            if "libLLVM" not in maps.read():
                return
    except OSError:
        return
    flags = sys.getdlopenflags()
    sys.setdlopenflags(flags | os.RTLD_DEEPBIND)
    try:
        importlib.import_module("triton")
    finally:
        sys.setdlopenflags(flags)


@functools.cache
def _built(name: str, display: str):
    chosen = model(name)
    try:  # the optional extra: imported on first use (PyTorch takes seconds)
        _import_triton_apart()
        package = importlib.import_module(chosen.package)
        import torch
    except (ImportError, OSError, RuntimeError) as why:  # e.g. a torchvision of another torch
        raise ImportError(
            f"blurlab.metrics.{name}: {chosen.package} is installed but does not load ({why}); "
            f"install PyTorch and torchvision of one build, then {INSTALL}"
        ) from why
    # pyfvvdp logs a warning per frame for values outside [0, 1]; the frames given are clipped.
    logging.getLogger(chosen.package).setLevel(logging.ERROR)
    build = getattr(package, chosen.builder)
    return build(
        display_name=display, heatmap=None, quiet=True, device=torch.device("cpu"), **chosen.options
    )


def judge(name: str, reference, test, fps: float = DEFAULT_FPS, display: str = DISPLAY) -> float:
    """Model `name`'s quality in JOD of sequence `test` against `reference` (both (N >= 2, H,
    W, 3|4) linear colour, clipped to [0, 1] and sRGB-encoded as the display shows them) at
    `fps` frames per second on the package's display model `display`. Higher is better; 10: no
    visible difference."""
    chosen = model(name)
    if not available(name):
        raise ImportError(f"blurlab.metrics.{name} needs {chosen.label}: {INSTALL}")
    reference, test = check_sequence(reference, "reference"), check_sequence(test, "test")
    if reference.shape[:3] != test.shape[:3]:
        raise ValueError(
            f"blurlab.metrics: sequences differ in shape: {reference.shape} and {test.shape}"
        )
    if not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
        raise ValueError(f"blurlab.metrics.{name}: fps must be a finite number > 0, not {fps!r}")

    def shown(frames):
        return np.ascontiguousarray(io.linear_to_srgb(frames[..., :3]), np.float32)

    quality, _ = _built(name, display).predict(
        shown(test), shown(reference), dim_order="FHWC", frames_per_second=float(fps)
    )
    return float(quality)


def colorvideovdp(reference, test, fps: float = DEFAULT_FPS, display: str = DISPLAY) -> float:
    """ColorVideoVDP's quality in JOD of sequence `test` against `reference`, as `judge`
    gives it (pycvvdp's display model `display`)."""
    return judge("colorvideovdp", reference, test, fps, display)


def fovvideovdp(reference, test, fps: float = DEFAULT_FPS, display: str = DISPLAY) -> float:
    """FovVideoVDP's quality in JOD of sequence `test` against `reference`, as `judge` gives
    it (pyfvvdp's display model `display`, not foveated)."""
    return judge("fovvideovdp", reference, test, fps, display)


_FUNCTIONS = {"colorvideovdp": colorvideovdp, "fovvideovdp": fovvideovdp}
for _model in MODELS.values():
    declare_optional(_model.name, _model.label, _model.doc, INSTALL)
    if available(_model.name):
        register(
            Metric(
                name=_model.name,
                doc=_model.doc,
                spec="§21.3",
                higher_is_better=True,
                range=(-np.inf, 10.0),
                reference="antialiased",
                numpy=_FUNCTIONS[_model.name],
                label=_model.label,
                unit="JOD",
                sequence=True,
            )
        )
