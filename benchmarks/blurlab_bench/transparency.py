"""The transparency benchmark: the four ways to blur translucency (docs/spec.md §20.4) on the
transparency scenes, for the reconstruction filters, the coverage gather and the engines'
filters, against the antialiased reference; and on the cost scenes, what the layered approach
costs next to the method alone, what the translucent objects add to the G-buffer, and a whole
frame's time (G-buffer and blur) against the same scene with its translucent objects drawn
opaque (docs/transparency.md)."""

from __future__ import annotations

import statistics

import numpy as np

from blurlab import blender, metrics
from blurlab.blender import crosscheck
from blurlab.methods import blur, example_method, method_instant, translucent_layer_method
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies import transparency

from .core import Benchmark, register
from .timing import median_passes, spin_up, split


def layer_cost(ctx, scene_name: str, method: str, size, runs: int = 10) -> dict:
    """GPU time of `method` on the scene's frame as engines run it (translucency="composite")
    and with the layered approach, median over `runs` timed calls each, and their ratio; and
    where layered's time goes, medians of its parts: the opaque layer's blur, the translucent
    layer's blur ("translucent_" passes), the compositing pass, and the layer's split, which
    runs once per frame (frame.timings, beside the G-buffer's passes; docs/spec.md §20.4).
    "drawn_opaque_ms": the method on the scene with its translucent objects drawn opaque
    (transparency.drawn_opaque_scene), where it blurs them with their own motion."""
    scene = scenes.get(scene_name)
    frame = ctx.render(scene, size, instant=method_instant(method))
    drawn_opaque = ctx.render(
        transparency.drawn_opaque_scene(scene_name), size, instant=method_instant(method)
    )
    drawn_opaque_ms = median_passes(ctx, drawn_opaque, method, runs)[0]["total"]
    times = {}
    parts = {"opaque": [], "layer": [], "over": []}
    for approach in ("composite", "layered"):
        # compiled, warmed up, and on a GPU its clocks up: rendering the frame and the last
        # method's CPU work leave it idle
        spin_up(ctx, lambda approach=approach: blur(ctx, frame, method, translucency=approach))
        totals = []
        for _ in range(runs):
            result = blur(ctx, frame, method, translucency=approach)
            totals.append(result.total_ms)
            if approach == "layered":
                timings = {name: t.ms for name, t in result.timings.items()}
                over = timings.pop("translucency_over")
                layer = sum(ms for name, ms in timings.items() if name.startswith("translucent_"))
                parts["over"].append(over)
                parts["layer"].append(layer)
                parts["opaque"].append(result.total_ms - over - layer)
        times[approach] = float(np.median(totals))
    return {
        "scene": scene_name,
        "method": method,
        "composite_ms": times["composite"],
        "layered_ms": times["layered"],
        "ratio": times["layered"] / times["composite"],
        **{f"{part}_ms": float(np.median(values)) for part, values in parts.items()},
        "split_ms": frame.timings["translucent_split"].ms,
        "drawn_opaque_ms": drawn_opaque_ms,
    }


def gbuffer_cost(ctx, scene_name: str, size, runs: int = 10) -> dict:
    """GPU time of the scene's G-buffer with its translucent objects (their fragment lists and
    resolve included), without them, and with them drawn opaque, median over `runs` renders
    each, and the first two's difference: what the translucent layer adds to the G-buffer
    (docs/spec.md §20)."""
    times = {}
    for label, scene in (
        ("with", scenes.get(scene_name)),
        ("without", transparency.opaque_scene(scene_name)),
        ("drawn_opaque", transparency.drawn_opaque_scene(scene_name)),
    ):
        spin_up(ctx, lambda scene=scene: ctx.render(scene, size))
        times[label] = float(
            np.median([ctx.render(scene, size).timings["gbuffer"].ms for _ in range(runs)])
        )
    return {
        "scene": scene_name,
        "with_ms": times["with"],
        "without_ms": times["without"],
        "layer_ms": times["with"] - times["without"],
        "drawn_opaque_ms": times["drawn_opaque"],
    }


def frame_cost(layer: dict, gbuffer: dict) -> dict:
    """A frame's time, G-buffer and blur, from layer_cost and gbuffer_cost on one scene: with
    the layered approach (the G-buffer with its translucent layer, the layer's split and the
    layered blur), as engines blur it (the same G-buffer, translucency="composite"), and as
    blurlab drew the scene before it had a translucent layer (its translucent objects drawn
    opaque, the method alone); and layered's frame over each of the other two."""
    layered = gbuffer["with_ms"] + layer["split_ms"] + layer["layered_ms"]
    composite = gbuffer["with_ms"] + layer["composite_ms"]
    drawn_opaque = gbuffer["drawn_opaque_ms"] + layer["drawn_opaque_ms"]
    return {
        "scene": layer["scene"],
        "method": layer["method"],
        "layered_ms": layered,
        "composite_ms": composite,
        "drawn_opaque_ms": drawn_opaque,
        "over_composite": layered / composite,
        "over_drawn_opaque": layered / drawn_opaque,
    }


def _transparency(ctx, size, p, out) -> None:
    methods = split(p["methods"]) or transparency.single_frame_methods()
    cost_scenes = split(p["cost_scenes"])
    for scene in cost_scenes:  # an unknown name fails here, not after the scoring
        scenes.get(scene)
    shown: dict = {}
    table = transparency.evaluate(
        ctx, split(p["scenes"]) or None, methods, size, p["reference_samples"] or None, shown
    )
    summary = transparency.summary(table)
    for approach, row in summary["median_per_approach"].iterrows():
        out.figure(f"{approach}: median PSNR", row.psnr, "dB")
        out.figure(f"{approach}: median FLIP", row.flip, "")
    out.figure(
        "layered − best of the other three, median over (scene, method): PSNR",
        summary["median_layered_gain_db"],
        "dB",
    )
    out.figure(
        "best of the other three − layered, median over (scene, method): FLIP",
        summary["median_layered_gain_flip"],
        "",
    )
    per_scene = table.groupby(["scene", "translucency"])[["psnr", "flip"]].median()
    gain = summary["median_gain_per_scene"]
    out.table(
        "median over the methods, per scene and approach",
        [("scene", ""), ("translucency", ""), ("PSNR", "dB"), ("FLIP", "")],
        [[s, a, row.psnr, row.flip] for (s, a), row in per_scene.iterrows()],
    )
    out.table(
        "layered's margin over the best other approach, median over the methods",
        [("scene", ""), ("PSNR", "dB"), ("FLIP", "")],
        [[s, row.psnr, row.flip] for s, row in gain.iterrows()],
    )
    ceiling = transparency.layer_error(ctx, shown, size, p["reference_samples"] or None)
    layered = per_scene.xs("layered", level="translucency")["psnr"]
    out.table(
        "the layer's blur alone: the coverage gather's layer over the exact blur of the opaque "
        "layer, and layered (median over the methods)",
        [("scene", ""), ("layer's blur alone", "dB"), ("layered", "dB")],
        [[row.scene, row.psnr, layered[row.scene]] for row in ceiling.itertuples()],
    )
    out.table(
        "every scene, method and approach",
        [
            ("scene", ""),
            ("method", ""),
            ("translucency", ""),
            ("PSNR", "dB"),
            ("FLIP", ""),
            ("reference samples", ""),
        ],
        table[["scene", "method", "translucency", "psnr", "flip", "reference_samples"]]
        .to_numpy()
        .tolist(),
    )
    costs = [
        layer_cost(ctx, scene, method, size, p["runs"])
        for scene in cost_scenes
        for method in methods
    ]
    out.table(
        "time of the method alone (composite) and layered, medians; layered's parts, and the "
        "layer's split, once per frame",
        [
            ("scene", ""),
            ("method", ""),
            ("composite", "ms"),
            ("layered", "ms"),
            ("layered / composite", "x"),
            ("opaque blur", "ms"),
            ("layer blur", "ms"),
            ("over", "ms"),
            ("split per frame", "ms"),
        ],
        [
            [
                c["scene"],
                c["method"],
                c["composite_ms"],
                c["layered_ms"],
                c["ratio"],
                c["opaque_ms"],
                c["layer_ms"],
                c["over_ms"],
                c["split_ms"],
            ]
            for c in costs
        ],
    )
    gbuffers = {scene: gbuffer_cost(ctx, scene, size, p["runs"]) for scene in cost_scenes}
    out.table(
        "the G-buffer with the scene's translucent objects, without them, and with them drawn "
        "opaque, medians",
        [
            ("scene", ""),
            ("with", "ms"),
            ("without", "ms"),
            ("the translucent layer's part", "ms"),
            ("drawn opaque", "ms"),
        ],
        [
            [g["scene"], g["with_ms"], g["without_ms"], g["layer_ms"], g["drawn_opaque_ms"]]
            for g in gbuffers.values()
        ],
    )
    frames = [frame_cost(c, gbuffers[c["scene"]]) for c in costs]
    out.table(
        "a frame, G-buffer and blur: layered, as engines blur it (composite), and with the "
        "translucent objects drawn opaque; layered's frame over each",
        [
            ("scene", ""),
            ("method", ""),
            ("layered", "ms"),
            ("composite", "ms"),
            ("drawn opaque", "ms"),
            ("layered / composite", "x"),
            ("layered / drawn opaque", "x"),
        ],
        [
            [
                f["scene"],
                f["method"],
                f["layered_ms"],
                f["composite_ms"],
                f["drawn_opaque_ms"],
                f["over_composite"],
                f["over_drawn_opaque"],
            ]
            for f in frames
        ],
    )
    for scene in cost_scenes:
        ratios = [c["ratio"] for c in costs if c["scene"] == scene]
        out.figure(
            f"{scene}: layered / composite time, median over the methods",
            statistics.median(ratios),
            "x",
        )
        out.figure(f"{scene}: layered / composite time, fewest over the methods", min(ratios), "x")
        for key, label in (("over_composite", "composite"), ("over_drawn_opaque", "drawn opaque")):
            ratios = [f[key] for f in frames if f["scene"] == scene]
            out.figure(
                f"{scene}: frame with layered / frame {label}, median over the methods",
                statistics.median(ratios),
                "x",
            )


register(
    Benchmark(
        "transparency",
        "the four ways to blur translucency on the transparency scenes: PSNR and FLIP against "
        "the antialiased reference per approach, layered's margin, and its cost",
        {
            "scenes": Param("", str, "comma-separated scenes (empty: the transparency tag)"),
            "methods": Param("", str, "comma-separated methods (empty: filters and engines)"),
            "reference_samples": Param(0, int, "N of the references (0: from the motion)", 0),
            # The three where translucent surfaces move: a still wall behind a moving pane (the
            # method alone exits early almost everywhere), and two whose opaque layers move too.
            "cost_scenes": Param(
                "moving_glass,sparks_over_mover,smoke_pan",
                str,
                "comma-separated scenes the costs are timed on",
            ),
            "runs": Param(5, int, "timed runs per method and approach (medians)", 1, 1000),
        },
        _transparency,
        {"tiny": (48, 27), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {
            "tiny": {
                "scenes": "moving_glass,sparks_over_mover",
                # the examples' tile filter and the method that blurs the translucent layer
                "methods": f"{example_method()},{translucent_layer_method()}",
                "reference_samples": 8,
                "cost_scenes": "moving_glass,sparks_over_mover",
                "runs": 1,
            },
            "gpu": {"runs": 20},
        },
    )
)


def _transparency_cycles(ctx, size, p, out) -> None:
    rows = []
    for name, make in crosscheck.TRANSLUCENT_SCENES.items():
        scene = make()
        cycles = blender.render(scene, size, samples=p["cycles_samples"], seed=1).color
        shutter = blender.cycles_shutter(scene.shutter)
        reference = ctx.reference(
            scene, size, shutter, samples=p["reference_samples"], antialias=True, progress=False
        ).color
        psnr = metrics.psnr(reference, cycles)
        rows.append([name, psnr])
        out.figure(f"{name}: PSNR of Cycles against the antialiased reference", psnr, "dB")
    out.table(
        "Cycles (box filter) against blurlab's antialiased reference",
        [("scene", ""), ("PSNR", "dB")],
        rows,
    )


register(
    Benchmark(
        "transparency_cycles",
        "Cycles' transparent and emission shader mixes against blurlab's antialiased reference "
        "on translucent scenes (needs bpy)",
        {
            "cycles_samples": Param(4096, int, "Cycles samples per pixel", 1, 1 << 20),
            "reference_samples": Param(8192, int, "sub-frames of blurlab's reference", 1),
        },
        _transparency_cycles,
        {"tiny": (32, 18), "software": (320, 180), "gpu": (320, 180)},
        {"tiny": {"cycles_samples": 16, "reference_samples": 16}},
        needs=("bpy",),
    )
)
