"""GPU metrics issued now and read later (docs/spec.md §6.3): `MetricQueue`, `MetricBatches`,
and the reductions a sweep issues for the registered metrics it computes (`issue_reductions`,
`reduced_values`), each pass once per pair.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

from .. import _core
from ..twins import flip as flip_twin
from .flip_gpu import flip_mean, flip_textures
from .reductions import (
    PreparedReference,
    check_same_size,
    mean_squared,
    mse_ssim_of_totals,
    squared_error_pass,
    ssim_pass,
)
from .registry import REFERENCES, Metric


class MetricQueue:
    """GPU metrics issued now and read together later (docs/spec.md §6.3): `mse`, `mse_ssim`
    and `flip` dispatch their passes and return their place in the batch; `read()` waits for
    the GPU once and returns every value in the order issued, each equal bit for bit to what
    `gpu_mse` / `gpu_mse_ssim` / `gpu_flip` return for the same pair. Between the two the CPU
    goes on issuing work (the next evaluation's filter) while the GPU runs, instead of waiting
    for each scalar. `seal()` ends a batch without waiting (a fence is queued after it), so
    that with two queues in turn the GPU works through one batch while the CPU issues the next
    and reads the one before. The compared textures may go back to the pool once issued: GL
    runs the reduction before any later pass that reuses them."""

    def __init__(self, ctx):
        self._ctx = ctx
        self._core = _core.ReductionQueue(ctx.native)
        self._finish: list = []  # per reduction issued: totals -> the metric's value
        self._sealed = False

    def _issuing(self) -> None:
        if self._sealed:
            raise RuntimeError("blurlab.metrics.MetricQueue: read() a sealed batch before issuing")

    def seal(self) -> None:
        """Ends the batch: its read-back starts on the GPU; `read()` then waits only for it."""
        self._core.seal()
        self._sealed = bool(self._finish)

    def __len__(self) -> int:
        return len(self._finish)

    def mse(self, a, b) -> int:
        """Issues `gpu_mse(ctx, a, b)`; returns its index in `read()`'s list."""
        self._issuing()
        check_same_size(a, b, "MetricQueue.mse")
        squared_error_pass(self._ctx).issue_squared_error(a.native, b.native, self._core)
        shape = a.shape
        self._finish.append((True, lambda totals: mean_squared(totals[0], shape)))
        return len(self._finish) - 1

    def mse_ssim(self, reference, test, layout: str | None = None) -> int:
        """Issues `gpu_mse_ssim(ctx, reference, test)`: `reference` a `PreparedReference`
        (prepare_reference; `layout` is then its own) or a texture (both images' moments
        blurred, in `layout` as `gpu_mse_ssim` says). Returns its index in `read()`'s list,
        where its value is the (mse, ssim) tuple."""
        self._issuing()
        if isinstance(reference, PreparedReference):
            reference.pass_against(test, "MetricQueue.mse_ssim").issue_mse_ssim_prepared(
                *reference.natives(test), self._core
            )
        else:
            if getattr(reference, "native", None) is None:
                raise TypeError(
                    "blurlab.metrics.MetricQueue.mse_ssim: compares with a PreparedReference "
                    f"(prepare_reference) or a texture, not {type(reference).__name__}"
                )
            check_same_size(reference, test, "MetricQueue.mse_ssim")
            ssim_pass(self._ctx, layout).issue_mse_ssim(reference.native, test.native, self._core)
        shape = test.shape
        self._finish.append((True, lambda totals: mse_ssim_of_totals(totals, shape)))
        return len(self._finish) - 1

    def flip(self, reference, test, ppd: float = flip_twin.DEFAULT_PPD) -> int:
        """Issues `gpu_flip(ctx, reference, test, ppd)`; returns its index in `read()`'s list.
        Its partial sums stay in a small pooled texture until `read()` downloads them."""
        self._issuing()
        error, partials = flip_textures(self._ctx, reference, test, ppd)
        self._ctx.recycle(error)
        shape = reference.shape
        self._finish.append((False, lambda: flip_mean(self._ctx, partials, shape)))
        return len(self._finish) - 1

    def read(self) -> list:
        """The values of every metric issued since the last read, in order; empties the queue.
        One wait for the GPU (none when nothing is pending). Raises ``blurlab.StaleReadback``
        (the queue emptied) where the partial sums read back are not what the passes wrote."""
        finish, self._finish, self._sealed = self._finish, [], False
        totals = iter(self._core.read())
        return [f(next(totals)) if reads_totals else f() for reads_totals, f in finish]


class MetricBatches:
    """Batches of `size` evaluations whose metrics are read back one batch behind: two
    MetricQueues in turn, so that the CPU reads batch n only once batch n + 1 is issued and the
    GPU never waits for the CPU's read (docs/spec.md §6.3). Issue an evaluation's metrics into
    `queue`, then `add(item)` it; `add` and `flush` return (item, values) for each evaluation
    whose batch has been read, in order, `values` being its batch's `MetricQueue.read()`, or
    None where that read raised ``StaleReadback``: the caller evaluates those items again."""

    def __init__(self, ctx, size: int):
        if isinstance(size, bool) or not isinstance(size, int) or size < 1:
            raise ValueError(
                f"blurlab.metrics.MetricBatches: size must be an integer >= 1, not {size!r}"
            )
        self.size = size
        self._queues = [MetricQueue(ctx), MetricQueue(ctx)]
        self._items: list = []  # of the batch being issued
        self._sealed: list = []  # the batch before, sealed and not read yet

    @property
    def queue(self) -> MetricQueue:
        """The queue that the current evaluation's metrics go to."""
        return self._queues[0]

    def add(self, item) -> list[tuple[object, list]]:
        self._items.append(item)
        if len(self._items) < self.size:
            return []
        self.queue.seal()
        ready = self._read_sealed()
        self._sealed, self._items = self._items, []
        self._queues.reverse()
        return ready

    def flush(self) -> list[tuple[object, list | None]]:
        """Every evaluation not read yet."""
        ready = self._read_sealed()
        values = _read_or_none(self.queue)
        ready += [(item, values) for item in self._items]
        self._items = []
        return ready

    def _read_sealed(self) -> list[tuple[object, list | None]]:
        values = _read_or_none(self._queues[1])
        ready = [(item, values) for item in self._sealed]
        self._sealed = []
        return ready


def _read_or_none(queue: MetricQueue) -> list | None:
    """The queue's values, or None where its read-back was refused (StaleReadback)."""
    try:
        return queue.read()
    except _core.StaleReadback:
        return None


def issue_reductions(
    queue,
    metrics: Sequence[Metric],
    textures: Mapping[str, object],
    prepared: Callable[[str], PreparedReference],
    test,
) -> dict:
    """Issues into `queue` (a MetricQueue, or an object whose mse, mse_ssim and flip answer at
    once) the GPU reductions that `metrics` need, of the texture `test` against `textures`
    ({reference kind: texture}, REFERENCES). Each pass runs once per reference: squared error
    and SSIM against one reference come from one mse_ssim against `prepared(kind)`, that
    reference prepared. Returns {(reduction, kind): what the queue returned}, "mse_ssim"
    standing for both; `reduced_values` turns it, read back, into each metric's value."""
    needed = {(m.reduction, m.reference) for m in metrics if m.reduction is not None}
    issued = {}
    for kind in (k for k in REFERENCES if any(ref == k for _, ref in needed)):
        if ("ssim", kind) in needed:
            issued[("mse_ssim", kind)] = queue.mse_ssim(prepared(kind), test)
        elif ("squared_error", kind) in needed:
            issued[("squared_error", kind)] = queue.mse(test, textures[kind])
        if ("flip", kind) in needed:
            issued[("flip", kind)] = queue.flip(textures[kind], test)
    return issued


def reduced_values(metrics: Sequence[Metric], got: Mapping[tuple, object]) -> dict[str, float]:
    """{name: value} of the `metrics` that have a reduction, from `got`: issue_reductions'
    keys with the values read back (MSE for squared_error, (MSE, SSIM) for mse_ssim)."""
    reduced = {}
    for (reduction, kind), value in got.items():
        if reduction == "mse_ssim":
            reduced[("squared_error", kind)], reduced[("ssim", kind)] = value
        else:
            reduced[(reduction, kind)] = value
    return {
        m.name: m.value_from_reduction(reduced[(m.reduction, m.reference)])
        for m in metrics
        if m.reduction is not None
    }
