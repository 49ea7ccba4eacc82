"""The metric registry: each metric registers one `Metric` in the module that implements it,
carrying what every study, chart, report and doc page needs to know of it: which way is
better, its range, HDR or LDR, its NumPy and GPU implementations, the reference it compares
with and its definition in docs/spec.md. docs/adding_a_metric.md walks through adding one.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass

import numpy as np

# What a metric compares an output with (docs/spec.md §11 "Which reference, for what"): the
# temporal reference samples pixel centres as the methods' G-buffers do; the antialiased one
# also jitters sub-pixel positions, as a path tracer converges.
REFERENCES = ("temporal", "antialiased")
# The reductions a sweep can issue on the GPU for a pair of textures (blurlab.metrics.queue):
# the summed squared error, the SSIM sum and the FLIP sum. Squared error and SSIM against the
# same reference come from one fused pass.
REDUCTIONS = ("squared_error", "ssim", "flip")


@dataclass(frozen=True)
class Metric:
    """A registered metric: a number computed from a reference image and a test image.

    `numpy(reference, test) -> float` takes (H, W, 3|4) linear colour arrays and is the
    definition in code; `gpu(ctx, reference, test) -> float` takes two textures and must match
    it within `tolerance` (tests/test_metric_registry.py checks every registered pair). A sweep
    computes a metric with a `reduction` on the GPU, batched (its value is
    `from_reduction(the reduction's value)`), and any other from the images read back.
    """

    name: str  # the column of sweep tables, and the name `metrics=` takes
    doc: str  # its definition in a sentence or two (docs/metrics.md)
    spec: str  # the docs/spec.md section that defines it, e.g. "§6"
    # True: higher is better; False: lower is better; None: `best` is best (e.g. a ratio).
    higher_is_better: bool | None
    range: tuple[float, float]  # [low, high] of its values (inclusive; ±inf allowed)
    numpy: Callable
    label: str  # what chart axes call it, e.g. "PSNR after tone mapping"
    unit: str = ""  # e.g. "dB"; "" for a pure number
    best: float | None = None  # the best value where higher_is_better is None
    hdr: bool = False  # True: unclipped linear colour (docs/spec.md §6.2); False: clipped to [0, 1]
    reference: str = "temporal"  # one of REFERENCES
    gpu: Callable | None = None
    # `gpu`'s keyword arguments that depend on the reference alone, from its host colour: a
    # sweep makes them once per reference, not once per evaluation (HDR-FLIP's exposure range)
    gpu_arguments: Callable[[np.ndarray], dict] | None = None
    reduction: str | None = None  # one of REDUCTIONS, for a sweep's batched GPU read-back
    from_reduction: Callable[[float], float] | None = None  # None: the reduction's value itself
    tolerance: float = 0.0  # |gpu - numpy| allowed, in the metric's unit
    # Computed by sweeps and the study when no metrics are named (an HDR metric on HDR scenes
    # only): a new metric is computed only where asked unless it sets this.
    default: bool = False
    # True: `numpy` takes sequences (N, H, W, C) of N >= 2 frames, the reference's and the
    # test's (docs/spec.md §21.3); sweeps of single frames refuse it.
    sequence: bool = False

    def __post_init__(self):
        where = f"blurlab.metrics: metric {self.name!r}"
        if not (isinstance(self.name, str) and self.name.isidentifier()):
            raise ValueError(f"blurlab.metrics: a metric name is an identifier, not {self.name!r}")
        if not (self.doc and self.spec.startswith("§") and self.label):
            raise ValueError(f"{where} needs a doc, a label and its docs/spec.md section (§n)")
        if self.higher_is_better not in (True, False, None):
            raise ValueError(f"{where}: higher_is_better is True, False or None")
        if (self.higher_is_better is None) != (self.best is not None):
            raise ValueError(f"{where}: give `best` exactly when higher_is_better is None")
        low, high = self.range
        if not low < high:
            raise ValueError(f"{where}: range must be (low, high) with low < high")
        if self.reference not in REFERENCES:
            raise ValueError(f"{where}: reference must be one of {REFERENCES}")
        if self.reduction is not None and self.reduction not in REDUCTIONS:
            raise ValueError(f"{where}: reduction must be None or one of {REDUCTIONS}")
        if not callable(self.numpy) or (self.gpu is not None and not callable(self.gpu)):
            raise TypeError(f"{where}: numpy (and gpu, if given) must be callable")
        if self.gpu_arguments is not None and (
            self.gpu is None or not callable(self.gpu_arguments)
        ):
            raise TypeError(f"{where}: gpu_arguments is a callable, given with gpu")

    @property
    def direction(self) -> str:
        """Which way is better, in words."""
        if self.higher_is_better is None:
            return f"best at {self.best:g}"
        return "higher is better" if self.higher_is_better else "lower is better"

    @property
    def axis_title(self) -> str:
        """A chart axis' title: label, unit and direction."""
        unit = f" ({self.unit})" if self.unit else ""
        return f"{self.label}{unit}, {self.direction}"

    def goodness(self, value):
        """`value` (a number or a pandas Series) on a scale where higher is always better: the
        value, its negative, or minus its distance from `best`. Rankings and Pareto fronts
        compare these."""
        if self.higher_is_better is None:
            return -abs(value - self.best)
        return value if self.higher_is_better else -value

    def value_from_reduction(self, reduced: float) -> float:
        return reduced if self.from_reduction is None else self.from_reduction(reduced)


_REGISTRY: dict[str, Metric] = {}
# Metrics of optional extras: {name: (what it is, what to install)}. Each is registered only
# where its extra is installed; asking for one elsewhere says what to install, and
# docs/metrics.md lists them apart, the same with or without the extra.
_OPTIONAL: dict[str, tuple[str, str, str]] = {}


def declare_optional(name: str, label: str, doc: str, needs: str) -> None:
    """Declares metric `name` (`label`, `doc` as its Metric's) as one of an optional extra
    (`needs`: the install line), whether or not it is installed here; the module registers it
    too where it is."""
    _OPTIONAL[name] = (label, doc, needs)


def _unknown(caller: str, names: list[str]) -> ValueError:
    missing = [n for n in names if n in _OPTIONAL]
    unknown = [n for n in names if n not in _OPTIONAL]
    parts = [f"unknown metrics {unknown}; choose from {registered()}"] if unknown else []
    if missing:
        needs = "; ".join(f"{n}: {_OPTIONAL[n][2]}" for n in missing)
        parts.append(f"metrics {missing} are not installed here ({needs})")
    return ValueError(f"{caller}: " + "; ".join(parts))


def register(metric: Metric) -> Metric:
    """Adds `metric` to the registry; its name must be new."""
    if not isinstance(metric, Metric):
        raise TypeError(f"blurlab.metrics.register takes a Metric, not {type(metric).__name__}")
    if metric.name in _REGISTRY:
        raise ValueError(
            f"blurlab.metrics: a metric {metric.name!r} is registered already; metric names "
            "are unique (unregister the old one first to replace it)"
        )
    _REGISTRY[metric.name] = metric
    return metric


def unregister(name: str) -> Metric:
    """Removes metric `name` from the registry and returns it (for a notebook or test that
    tries a metric out)."""
    metric = get(name)
    del _REGISTRY[name]
    return metric


def registered() -> list[str]:
    """Names of the registered metrics, in registration order (the order of table columns)."""
    return list(_REGISTRY)


def get(name: str) -> Metric:
    """The registered metric `name`."""
    if name not in _REGISTRY:
        if name in _OPTIONAL:
            raise _unknown("blurlab.metrics", [name])
        raise ValueError(f"blurlab.metrics: no metric {name!r}; registered metrics: {registered()}")
    return _REGISTRY[name]


def check_names(names: Iterable[str], caller: str, sequences: bool = False) -> tuple[str, ...]:
    """`names` as a tuple, each a registered metric; otherwise an error from `caller` that
    names the unknown ones and lists the registered ones. Metrics of sequences are refused
    unless `sequences` (the caller measures sequences of frames)."""
    if isinstance(names, str):
        raise TypeError(f"{caller}: metrics is a list of names, not the string {names!r}")
    names = tuple(names)
    unknown = [n for n in names if n not in _REGISTRY]
    if unknown:
        raise _unknown(caller, unknown)
    over_time = [n for n in names if _REGISTRY[n].sequence]
    if over_time and not sequences:
        raise ValueError(
            f"{caller}: {over_time} measure sequences of frames, not one frame; "
            "use them on a bl.sequence (docs/spec.md §21.3)"
        )
    return names


def default_names(hdr_scene: bool) -> tuple[str, ...]:
    """The metrics sweeps compute when none are named: those registered as `default`, the HDR
    ones only on an HDR scene (`Scene.hdr`, docs/spec.md §6.2)."""
    return tuple(n for n, m in _REGISTRY.items() if m.default and (hdr_scene or not m.hdr))


def cpu_scores(
    names: Iterable[str], references: Mapping[str, np.ndarray], test
) -> dict[str, float]:
    """{name: value} of the metrics `names` computed with their NumPy implementations:
    `references` maps each reference kind (REFERENCES) the metrics need to its colour. Each
    image goes to float64 once, not once per metric."""
    test = np.asarray(test, np.float64)
    colours = {kind: np.asarray(image, np.float64) for kind, image in references.items()}
    return {n: float(get(n).numpy(colours[get(n).reference], test)) for n in names}


def gpu_scores(
    ctx,
    names: Iterable[str],
    references: Mapping[str, object],
    test,
    arguments: Callable[[str], dict] | None = None,
) -> dict[str, float]:
    """{name: value} of the metrics `names` computed with their GPU implementations, read back
    at once: `references` maps each reference kind the metrics need to its texture, `test` is
    a texture, `arguments(name)` the metric's `gpu_arguments` of its reference where the
    caller made them (else `gpu` derives what it needs). For a metric with no batched
    reduction whose GPU version spares the CPU (HDR-FLIP at 1080p took seconds an evaluation
    on the CPU)."""
    given = arguments or (lambda name: {})
    return {
        n: float(get(n).gpu(ctx, references[get(n).reference], test, **given(n))) for n in names
    }


def _number(value: float) -> str:
    return {math.inf: "+inf", -math.inf: "-inf"}.get(value, f"{value:g}")


def reference_page() -> str:
    """docs/metrics.md: every registered metric's definition, direction, range and
    implementations, from the registry (`blurlab metrics` prints it)."""
    lines = [
        "# Metrics",
        "",
        "Generated from the registry (`python/blurlab/metrics/`) by "
        "`blurlab metrics > docs/metrics.md`;",
        "`tests/test_metric_registry.py` fails when it is out of date. Each metric is registered "
        "once, in",
        "the module that implements it, and sweeps, the study, charts and `recommend` read it "
        "from the",
        "registry: `bl.metrics.registered()`, `bl.metrics.get(name)`. docs/adding_a_metric.md "
        "adds one.",
        "",
        "| metric | better | range | colour | reference | on the GPU | by default | spec |",
        "|---|---|---|---|---|---|---|---|",
    ]
    # The optional extras' metrics are listed apart, so that the page is the same whether or
    # not they are installed.
    always = {name: m for name, m in _REGISTRY.items() if name not in _OPTIONAL}
    for name, m in always.items():
        gpu = f"`{m.reduction}` reduction" if m.reduction else ("yes" if m.gpu else "no")
        default = "HDR scenes" if m.default and m.hdr else ("yes" if m.default else "no")
        lines.append(
            f"| `{name}` | {m.direction} | [{_number(m.range[0])}, {_number(m.range[1])}] | "
            f"{'HDR' if m.hdr else 'LDR'} | {m.reference} | {gpu} | {default} | {m.spec} |"
        )
    for name, m in always.items():
        unit = f" in {m.unit}" if m.unit else ""
        lines += ["", f"## {name}: {m.label}", "", m.doc, ""]
        lines.append(
            f"- {m.direction.capitalize()}; values{unit} in [{_number(m.range[0])}, "
            f"{_number(m.range[1])}]; docs/spec.md {m.spec}."
        )
        colour = (
            "unclipped linear colour (HDR)" if m.hdr else "linear colour clipped to [0, 1] (LDR)"
        )
        lines.append(f"- Measures {colour} against the {m.reference} reference.")
        if m.sequence:
            lines.append("- Takes sequences of frames (N, H, W, C), N >= 2: bl.sequence's.")
        lines.append(f"- NumPy: `{_qualified(m.numpy)}`.")
        if m.gpu is not None:
            lines.append(f"- GPU: `{_qualified(m.gpu)}`, within {m.tolerance:g} of NumPy.")
        if m.reduction is not None:
            lines.append(
                f"- Sweeps reduce it on the GPU (`{m.reduction}`), read back in batches "
                "(docs/spec.md §6.3)."
            )
        else:
            lines.append("- Sweeps compute it on the CPU from the images read back.")
        if m.default:
            where = "on HDR scenes" if m.hdr else "on every scene"
            lines.append(f"- Computed by default {where}.")
    for name, (label, doc, needs) in _OPTIONAL.items():
        lines += ["", f"## {name}: {label} (optional)", "", doc, ""]
        lines.append(f"- Registered only where its optional extra is installed: `{needs}`.")
    return "\n".join(lines) + "\n"


def _qualified(function: Callable) -> str:
    module = getattr(function, "__module__", "")
    name = getattr(function, "__qualname__", repr(function))
    # The package's public name: blurlab.metrics.psnr, not blurlab.metrics.ldr.psnr.
    if module.startswith("blurlab.metrics."):
        module = "blurlab.metrics"
    return f"{module}.{name}"
