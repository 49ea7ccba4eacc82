"""Hatched materials (docs/spec.md §5).

``bl.Material.hatching(scheme, tam, scale)`` makes a material the G-buffer pass draws with a
tonal art map instead of shading: ``"six_way"`` (Praun et al. 2001: per-vertex weights of the
two nearest of 6 tones, blended per pixel) or ``"threshold"`` (Webb et al. 2002: a per-pixel
threshold test against the darkness). Hatched objects keep their depth, motion and object id,
so every motion-blur method blurs them.

The measurements that compare the two schemes are in blurlab.studies.hatching.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real
from pathlib import Path

import numpy as np

from .. import _core
from .tam import TAM, default_tam

SCHEMES = ("six_way", "threshold")
_CODES = {"six_way": 1, "threshold": 2}  # src/passes/gbuffer.h GBufferHatching::Scheme


@dataclass(frozen=True, eq=False)
class Hatching:
    """What a hatched material draws with: the scheme, the TAM, and how many times the TAM
    repeats per unit of texture coordinate."""

    scheme: str
    tam: TAM
    scale: float

    def draw(self, ctx, entry) -> None:
        """Fills a G-buffer draw's hatching entry (_core.GBufferHatching, by name)."""
        low, high, thresholds = self.tam.textures(ctx)
        entry.scheme = _core.GBufferHatching.Scheme(_CODES[self.scheme])
        entry.scale = float(self.scale)
        if self.scheme == "six_way":
            entry.tam_low, entry.tam_high = low, high
        else:
            entry.tam_low, entry.tam_high = thresholds, None


def hatch(scheme: str, tam, scale: float) -> Hatching:
    """The checked hatching of a material; ``bl.Material.hatching`` documents the arguments."""
    if scheme not in SCHEMES:
        raise ValueError(f"blurlab: hatching scheme must be one of {SCHEMES}, not {scheme!r}")
    if tam is None:
        tam = default_tam()
    elif isinstance(tam, np.ndarray):
        tam = _single_image_tam(tam)
    elif isinstance(tam, (str, Path)) and Path(tam).is_dir():
        tam = TAM.read(tam)
    elif not isinstance(tam, TAM):
        raise ValueError(
            "blurlab: hatching tam must be a bl.tam.TAM, a (6, S, S) float array of ink, "
            f"a folder written by TAM.write, or None (the default TAM), not {tam!r:.80}"
        )
    if isinstance(scale, bool) or not isinstance(scale, Real) or not math.isfinite(scale):
        raise ValueError(f"blurlab: hatching scale must be a finite number > 0, not {scale!r}")
    if scale <= 0:
        raise ValueError(f"blurlab: hatching scale must be > 0, not {scale!r}")
    return Hatching(scheme, tam, float(scale))


def _single_image_tam(array: np.ndarray) -> TAM:
    """A (6, S, S) ink array as a TAM whose coarser levels are 2×2 averages (down to 8)."""
    if array.ndim != 3 or array.shape[0] != 6 or array.shape[1] != array.shape[2]:
        raise ValueError(
            f"blurlab: hatching tam array must have shape (6, S, S), not {array.shape}"
        )
    if array.dtype.kind != "f" and array.dtype != np.uint8:
        raise ValueError(
            f"blurlab: hatching tam array must be float ink in [0, 1] or uint8, not {array.dtype}"
        )
    try:
        levels = [np.asarray(array / 255.0 if array.dtype == np.uint8 else array, np.float32)]
        while levels[-1].shape[1] > 8 and levels[-1].shape[1] % 2 == 0:
            s = levels[-1].shape[1] // 2
            levels.append(levels[-1].reshape(6, s, 2, s, 2).mean((2, 4)))
        return TAM(levels)
    except ValueError as error:
        raise ValueError(str(error).replace("tam tones", "hatching tam")) from None


# --- measurements --------------------------------------------------------------------------
