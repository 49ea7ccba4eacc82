"""The blurlab suite (docs/spec.md §24, docs/suite.md): one versioned benchmark that any method
can earn a card from. `definition` holds version 1's categories and presets, `content` its
hash, `run` writes a card, `compare` sets cards of one suite side by side."""

from .compare import compare, compare_text, load_card
from .content import suite_identity
from .definition import PRESETS, VERSION, categories
from .run import run_suite

__all__ = [
    "PRESETS",
    "VERSION",
    "categories",
    "compare",
    "compare_text",
    "load_card",
    "run_suite",
    "suite_identity",
]
