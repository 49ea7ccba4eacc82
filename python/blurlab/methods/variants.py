"""Alternative layouts of one pass, each a set of #defines that gives the same result (or one
whose difference is measured and documented), of which benchmarks time every one on a GPU
and the fastest becomes the default: TileMax's work group (tile_filter.TILE_MAX_VARIANTS),
engine_eevee's tile passes (eevee.TILE_PICK_VARIANTS), gather_coverage's film filter
(coverage.FILM_VARIANTS), gather_coverage's gather (coverage.GATHER_VARIANTS)."""

from __future__ import annotations

import contextlib
import contextvars

from . import plans


class PassVariants:
    """`variants`: name -> the #defines of that layout; `default` is used unless a
    `use(name)` block is active. `what` names the pass in error messages."""

    def __init__(self, what: str, variants: dict[str, dict], default: str):
        if default not in variants:
            raise ValueError(f"blurlab: {what} default {default!r} is not one of its variants")
        self.what, self.variants, self.default = what, variants, default
        self._chosen = contextvars.ContextVar(f"blurlab_{what}_variant", default=None)

    def make_default(self, name: str) -> None:
        """Makes variant `name` the default for the rest of the process (a benchmark's
        option). Unlike use(), dispatch plans go on being recorded and replayed: call it before
        the first method runs, as a plan recorded earlier would replay the old default."""
        if name not in self.variants:
            raise ValueError(
                f"blurlab: no {self.what} variant {name!r}; the variants are {list(self.variants)}"
            )
        self.default = name

    def chosen(self) -> str:
        """The variant in force: the innermost use() block's, else the default."""
        return self._chosen.get() or self.default

    def defines(self) -> dict:
        """The #defines of the variant in force."""
        return dict(self.variants[self.chosen()])

    @contextlib.contextmanager
    def use(self, name: str):
        """Inside the block the pass takes variant `name` (for benchmarks and tests), and no
        dispatch plan is recorded or replayed, as plans do not know the variant."""
        if name not in self.variants:
            raise ValueError(
                f"blurlab: no {self.what} variant {name!r}; the variants are {list(self.variants)}"
            )
        token = self._chosen.set(name)
        try:
            with plans.disabled():
                yield
        finally:
            self._chosen.reset(token)
