"""Benchmarks as a registry (core.py): each benchmark is registered once, with its parameters,
sizes and runner, by one of the modules imported here; `blurlab bench` runs them and keeps
their latest records in benchmarks/records.jsonl, from which report.py generates
docs/benchmarks.md. It is a development package of the checkout, which the wheel does not ship:
`blurlab bench` finds it beside the source it runs from, or on the path. The library never
imports it."""

# each module registers its own benchmarks
from . import frame, filters, sweeps, quality, controls, soak, transparency  # noqa: F401, I001
from . import auto_rules, directions, random_scenes, rankings, taps, temporal  # noqa: F401
from . import auto_holds, first_example, godot_fixes, perceptual, queue_depth, suite  # noqa: F401
from .core import (
    Benchmark,
    Measured,
    Unavailable,
    benchmark,
    merged,
    names,
    read_records,
    register,
    run_benchmark,
    validate,
    write_records,
)

__all__ = [
    "Benchmark",
    "Measured",
    "Unavailable",
    "benchmark",
    "merged",
    "names",
    "read_records",
    "register",
    "run_benchmark",
    "validate",
    "write_records",
]
