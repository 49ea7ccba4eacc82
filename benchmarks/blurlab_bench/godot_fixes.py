"""The godot_fixes benchmark: engine_godot's fixes each on and off on the failure scene it
addresses (blurlab.studies.godot_fixes, docs/failure_cases.md)."""

from __future__ import annotations

from blurlab.methods.params import Param
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies import godot_fixes

from .core import Benchmark, register


def _godot_fixes(ctx, size, p, out) -> None:
    rows = godot_fixes.measure(ctx, size, p["reference_samples"] or "auto")
    for scene, label, region, on, off in rows:
        out.figure(f"{scene}, {label}, {region}: on − off", on - off, "dB")
    out.table(
        f"{godot_fixes.fixed_method()} with each fix on and off, PSNR against the reference",
        [("scene", ""), ("fix", ""), ("pixels", ""), ("on", "dB"), ("off", "dB")],
        rows,
    )


register(
    Benchmark(
        "godot_fixes",
        f"{godot_fixes.fixed_method()}'s near-plane correction, depth velocity and clamp, each on "
        "and off on the failure scene it addresses: PSNR against the reference",
        {"reference_samples": Param(0, int, "N of the references (0: from the motion)", 0)},
        _godot_fixes,
        {"tiny": (64, 36), "software": (160, 90), "gpu": DEFAULT_SIZE},
        {"tiny": {"reference_samples": 8}},
    )
)
