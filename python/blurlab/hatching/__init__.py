"""Hatching: the tonal art maps (tam.py) and the hatching a material carries (patterns.py,
offered here as ``bl.hatching.SCHEMES``, ``bl.hatching.hatch``)."""

from .patterns import SCHEMES, Hatching, hatch

__all__ = ["SCHEMES", "Hatching", "hatch"]
