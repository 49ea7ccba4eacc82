"""NumPy references: the specification (SPEC.md) in code, float64 where it computes color.

Each GPU pass has its twin here, and the tests hold the GPU to it.
"""

from .hashing import pcg, rand
from .patterns import test_pattern

__all__ = ["pcg", "rand", "test_pattern"]
