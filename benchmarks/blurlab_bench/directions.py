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

from .core import Benchmark, register
from .timing import film_method, median_passes, method_runs, split

# The tile class of the two-direction path: a directions method's tile lists are named in the
# order of its class codes (Method.tile_lists).
TWO_DIRECTIONS = "gather_2"


def direction_methods() -> list[str]:
    """The methods that keep a number of velocity directions per tile (a `directions`
    parameter)."""
    return [name for name in methods() if "directions" in method(name).params]


def direction_runs() -> list[tuple]:
    """(label, method, parameters): each method that keeps a number of velocity directions per
    tile (its `directions` parameter) at every number it allows, then film_method()."""
    runs = []
    for name in direction_methods():
        declared = method(name).params["directions"]
        for count in range(declared.low, declared.high + 1):
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
                code = method(name_).tile_lists.index(TWO_DIRECTIONS)
                two = float(np.mean(classes[..., 3] == code))
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
        f"{' and '.join(direction_methods())} with one velocity direction per tile against two, "
        f"and {film_method()}, on the scenes where motions cross: PSNR against both references, "
        "two-direction tiles, ms",
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
