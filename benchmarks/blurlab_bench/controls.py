"""The blur-control scenes (docs/spec.md §12.1) measured: every method's error on fps_weapon (a
camera-held weapon at motion_blur 0 while the camera turns) and tracked_car (a panning shot),
against the reference that honours the same controls, with the error on the subject the
controls keep sharp (the weapon, the car) apart."""

from __future__ import annotations

import numpy as np

from blurlab.methods import methods, render_and_blur
from blurlab.methods.params import Param
from blurlab.metrics import psnr
from blurlab.scene import scenes

from .core import Benchmark, register
from .timing import gallery_methods

# The object each scene keeps still on screen: its pixels' error is reported apart.
SUBJECTS = {"fps_weapon": "weapon", "tracked_car": "car"}


def _names(text: str, allowed, what: str) -> list[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = sorted(set(names) - set(allowed))
    if unknown:
        raise ValueError(f"blurlab: blur_controls {what} {unknown}: from {', '.join(allowed)}")
    return names


def _blur_controls(ctx, size, p, out) -> None:
    names = _names(p["scenes"], SUBJECTS, "scenes") or list(SUBJECTS)
    chosen = _names(p["methods"], methods(), "methods") or methods()
    rows = []
    for name in names:
        scene = scenes.get(name)
        samples = p["reference_samples"] or "auto"
        reference = ctx.reference(scene, size, samples=samples, progress=False)
        expected = reference.color
        ids = [i for i, obj in enumerate(scene.objects) if obj.name == SUBJECTS[name]]
        for method in chosen:
            frame, result = render_and_blur(ctx, scene, method, size)
            subject = np.isin(frame.object_id, ids)
            color = result.color
            error = np.abs(np.clip(color, 0, 1) - np.clip(expected, 0, 1))[..., :3]
            ms = sum(t.ms for t in result.timings.values() if t is not None)
            rows.append(
                [
                    name,
                    method,
                    psnr(expected, color),
                    float(error[subject].mean()) if subject.any() else 0.0,
                    float(error[~subject].mean()),
                    ms,
                ]
            )
        out.figure(f"{name}: reference sub-frames", reference.samples, "")
    for name in names:
        scores = [r[2] for r in rows if r[0] == name]
        out.figure(f"{name}: median PSNR over methods", float(np.median(scores)), "dB")
    columns = [
        ("scene", ""),
        ("method", ""),
        ("PSNR", "dB"),
        ("subject mean abs error", "linear"),
        ("rest mean abs error", "linear"),
        ("passes", "ms"),
    ]
    out.table("every method against the reference, subject apart", columns, rows)


register(
    Benchmark(
        "blur_controls",
        "every method on the blur-control scenes (fps_weapon: a camera-held weapon at "
        "motion_blur 0; tracked_car: a panning shot): PSNR, the subject's error apart, ms",
        {
            "scenes": Param("", str, "comma-separated, from fps_weapon, tracked_car (empty: both)"),
            "methods": Param("", str, "comma-separated methods (empty: every one)"),
            "reference_samples": Param(0, int, "N of the reference (0: from the motion)", 0),
        },
        _blur_controls,
        {"tiny": (64, 36), "software": (160, 90), "gpu": (1280, 720)},
        {
            "tiny": {
                # a tile filter and a gather
                "methods": f"{gallery_methods('filter')[0]},{gallery_methods('gather')[0]}",
                "reference_samples": 8,
            }
        },
    )
)
