"""The NumPy twins: the specification (docs/spec.md) in code, float64 where it computes.

Each GPU pass has its twin here or, for a method's own pass, in its folder (twin.py beside
method.py), and the tests hold the GPU to it.
"""

from . import (
    flip,
    gathers,
    guertin2014,
    hatching,
    inputs,
    mcguire2012,
    motion_encoding,
    projection,
    sub_frames,
    taa,
)
from .hashing import pcg, rand
from .patterns import test_pattern

__all__ = [
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
    "sub_frames",
    "taa",
    "test_pattern",
]
