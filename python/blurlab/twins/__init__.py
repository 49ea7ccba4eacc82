"""The NumPy twins: the specification (docs/spec.md) in code, float64 where it computes.

Each GPU pass has its twin here, and the tests hold the GPU to it.
"""

from . import (
    accumulation,
    flip,
    gathers,
    guertin2014,
    hatching,
    inputs,
    mcguire2012,
    motion_encoding,
    projection,
    stochastic,
    taa,
)
from .hashing import pcg, rand
from .patterns import test_pattern

__all__ = [
    "accumulation",
    "flip",
    "gathers",
    "guertin2014",
    "hatching",
    "inputs",
    "mcguire2012",
    "motion_encoding",
    "pcg",
    "projection",
    "rand",
    "stochastic",
    "taa",
    "test_pattern",
]
