"""The crossing_directions benchmark: engine_unreal5 keeping one velocity direction per tile
against two (r.MotionBlur.Directions, docs/spec.md §17.7), and gather_coverage beside them,
on the scenes where motions cross: PSNR against the antialiased and the temporal reference,
the share of tiles that take the two-direction path, and each method's time."""

from __future__ import annotations

import numpy as np

from blurlab.methods import blur, method, methods
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies import peers
from blurlab.twins.unreal5 import GATHER_2

from .core import Benchmark, register
from .timing import film_method, median_passes, method_runs, split


def direction_runs() -> list[tuple]:
    """(label, method, parameters): each method that keeps a number of velocity directions per
    tile (its `directions` parameter) at every number it allows, then film_method()."""
    runs = []
    for name in methods():
        declared = method(name).params.get("directions")
        for count in range(declared.low, declared.high + 1) if declared else []:
            runs.append((f"{name}, directions={count}", name, {"directions": count}))
    return [*runs, (film_method(), film_method(), {})]


def _crossing_directions(ctx, size, p, out) -> None:
    runs = direction_runs() + method_runs([], configs=p["configs"])
    psnr = peers.SCORES["psnr"]
    rows = []
    for name in split(p["scenes"]):
        scene = scenes.get(name)
        frame = ctx.render(scene, size)
        samples = p["reference_samples"] or "auto"
        temporal = ctx.reference(scene, size, samples=samples, progress=False)
        antialiased = ctx.reference(
            scene, size, samples=temporal.samples, antialias=True, progress=False
        )
        for label, name_, params in runs:
            passes, _ = median_passes(ctx, frame, name_, p["runs"], **params)
            result = blur(ctx, frame, name_, timed=False, **params)
            classes = result.buffers.get("neighbors")
            two = None
            if "directions" in params:
                two = float(np.mean(classes[..., 3] == GATHER_2))
            rows.append(
                [
                    name,
                    label,
                    psnr(antialiased.color, result.color),
                    psnr(temporal.color, result.color),
                    two,
                    passes["total"],
                ]
            )
            out.figure(f"{name}, {label}: PSNR, antialiased reference", rows[-1][2], "dB")
    out.table(
        "each configuration on each scene, at its defaults otherwise",
        [
            ("scene", ""),
            ("method", ""),
            ("PSNR, antialiased reference", "dB"),
            ("PSNR, temporal reference", "dB"),
            ("tiles on the two-direction path", "share"),
            ("per-pass timers", "ms"),
        ],
        rows,
    )


register(
    Benchmark(
        "crossing_directions",
        "engine_unreal5 with one velocity direction per tile against two, and gather_coverage, "
        "on the scenes where motions cross: PSNR against both references, two-direction tiles, "
        "ms",
        {
            "scenes": Param("crossing,crossed_motions", str, "comma-separated scenes"),
            "configs": Param("", str, "more rows: METHOD:KEY=VALUE,... separated by ';'"),
            "runs": Param(5, int, "timed runs per configuration (medians)", 1, 1000),
            "reference_samples": Param(0, int, "N of the references (0: from the motion)", 0),
        },
        _crossing_directions,
        {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {
            "tiny": {"runs": 1, "reference_samples": 8},
            "software": {"runs": 3},
            "gpu": {"runs": 10},
        },
    )
)
