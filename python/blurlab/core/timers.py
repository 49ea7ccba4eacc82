"""GPU time, as a Timing that says which clock measured it (docs/spec.md §6.3): read at once,
read together after a batch (DeferredTimers), or read when first asked for (LazyTimers)."""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass

from .. import _core


@dataclass
class Timing:
    """One measured interval: milliseconds and the clock that measured them."""

    ms: float = math.nan
    clock: str = ""


class PendingTiming(Timing):
    """A Timing whose GPU result is read when `ms` is first asked for: the work it times was
    issued without a wait (Context.lazy_timers)."""

    def __init__(self, core: _core.Timer):
        self._core = core
        self._ms: float | None = None
        self.clock = core.clock

    @property
    def ms(self) -> float:
        if self._ms is None:
            self._ms = self._core.result()
            self._core = None  # the query is read once
        return self._ms

    @ms.setter
    def ms(self, value: float) -> None:
        self._ms = value


class LazyTimers:
    """Timers whose results are read when each Timing is first asked for (Context.lazy_timers):
    the G-buffer pass of ctx.render returns without waiting for the GPU (docs/spec.md §1.1)."""

    def __init__(self, context):  # a blurlab.core.context.Context
        self._context = context

    @contextmanager
    def timer(self):
        core = _core.Timer(self._context.native)
        core.start()
        timing = PendingTiming(core)
        try:
            yield timing
        finally:
            core.end()


class DeferredTimers:
    """Timers whose results are read together (Context.deferred_timers)."""

    def __init__(self, context):  # a blurlab.core.context.Context
        self._context = context
        self._pending: list[tuple[_core.Timer, Timing]] = []

    @contextmanager
    def timer(self):
        """Times the GPU work issued inside the block: yields a Timing, filled when the
        deferred_timers block ends."""
        core = _core.Timer(self._context.native)
        timing = Timing(clock=core.clock)
        core.start()
        try:
            yield timing
        finally:
            core.end()
            self._pending.append((core, timing))

    def read(self) -> None:
        """Fills every Timing of the timers that have ended (one wait for the GPU)."""
        pending, self._pending = self._pending, []
        # The last timer first: once the GPU has finished it, the earlier ones are there too.
        for core, timing in reversed(pending):
            timing.ms = core.result()
