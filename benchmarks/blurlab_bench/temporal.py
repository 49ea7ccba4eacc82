"""Benchmarks of sequences (docs/spec.md §21, docs/temporal.md): the orders of each method and
TAA on the built-in and failure scenes (temporal_orders), each method's error and instability
at 30 to 144 fps with a 180° shutter (frame_rate), and what a whole sequence with its
references, metrics and TAA costs (sequence)."""

from __future__ import annotations

import time

import numpy as np

from blurlab import metrics
from blurlab.methods import method as method_info
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.studies import temporal
from blurlab.temporal.sequences import sequence, still
from blurlab.temporal.taa import PARAMS as TAA_PARAMS
from blurlab.temporal.taa import taa, taa_values
from blurlab.twins.taa import resolve

from .core import Benchmark, register
from .timing import split

SEQUENCE_PARAMS = {
    "frames": Param(8, int, "frames measured per sequence", 2, 4096),
    "warmup": Param(4, int, "frames run before them, not measured (TAA's history fills)", 0),
    "reference_samples": Param(64, int, "sub-frames of each frame's reference", 1),
    "methods": Param("", str, "comma-separated methods (empty: every per-frame method)"),
}


def sequence_scenes(text: str) -> list[str]:
    """The scenes named in `text` (comma-separated), or the built-in and failure scenes."""
    return split(text) or scenes.names() + scenes.names("failure")


def _temporal_orders(ctx, size, p, out) -> None:
    methods = split(p["methods"]) or temporal.sequence_methods()
    table = temporal.evaluate_orders(
        ctx,
        sequence_scenes(p["scenes"]),
        methods,
        size,
        p["frames"],
        p["warmup"],
        p["reference_samples"],
        p["fps"],
    )
    summary = temporal.orders_summary(table)
    pairs = table[table["method"] != temporal.NO_METHOD][["scene", "method"]].drop_duplicates()
    out.figure("(scene, method) pairs", len(pairs), "")
    for measure, counts in summary["wins"].items():
        for order, count in counts.items():
            name = f"(scene, method) pairs where {order} is best by {measure}, ties included"
            out.figure(name, count, "")
    out.table(
        "per method: the order with the best median PSNR over the scenes, its margin over the "
        "next, the steadiest order, and the scenes where another order has the best PSNR",
        [
            ("method", ""),
            ("best by PSNR", ""),
            ("margin", "dB"),
            ("steadiest", ""),
            ("scenes where the winner flips", ""),
        ],
        summary["winners"][["method", "best", "margin_db", "steadiest", "flips"]]
        .to_numpy()
        .tolist(),
    )
    out.table(
        "medians over the scenes, per method and order",
        [("method", ""), ("order", ""), ("PSNR", "dB"), ("temporal instability", "")],
        summary["medians"]
        .reset_index()[["method", "order", "psnr", "temporal_instability"]]
        .to_numpy()
        .tolist(),
    )
    out.table(
        "every scene, method and order",
        [
            ("scene", ""),
            ("method", ""),
            ("order", ""),
            ("PSNR", "dB"),
            ("temporal instability", ""),
        ],
        table[["scene", "method", "order", "psnr", "temporal_instability"]].to_numpy().tolist(),
    )


register(
    Benchmark(
        "temporal_orders",
        "each method before TAA, after it and inside its history, on every built-in and "
        "failure scene: PSNR and temporal instability against the sequence reference, medians "
        "per method, which order wins and where the winner flips",
        {
            **SEQUENCE_PARAMS,
            "scenes": Param("", str, "comma-separated scenes (empty: built-in and failure)"),
            "fps": Param(60.0, float, "frame rate; the shutter is 180°", 1.0, 1000.0),
        },
        _temporal_orders,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (1280, 720)},
        {
            "tiny": {
                "scenes": "fan",
                "methods": ",".join(temporal.sequence_methods()[:1]),
                "frames": 2,
                "warmup": 1,
                "reference_samples": 4,
            },
            "gpu": {"frames": 16, "warmup": 8, "reference_samples": 256},
        },
    )
)


def _frame_rate(ctx, size, p, out) -> None:
    methods = split(p["methods"]) or temporal.sequence_methods()
    rates = [float(r) for r in split(p["rates"])]
    table = temporal.evaluate_frame_rates(
        ctx,
        sequence_scenes(p["scenes"]),
        methods,
        size,
        rates,
        p["frames"],
        p["warmup"],
        p["reference_samples"],
    )
    summary = temporal.frame_rate_summary(table)
    out.table(
        "medians over the scenes, per method, order and frame rate (180° shutter); relative "
        "MSE is the method's over the unblurred frames' at that rate, and its spread the "
        "largest over the smallest across the rates (1: the error follows the shutter alone)",
        [
            ("method", ""),
            ("order", ""),
            ("fps", "Hz"),
            ("PSNR", "dB"),
            ("temporal instability", ""),
            ("relative MSE", ""),
            ("relative MSE spread", "x"),
        ],
        summary[
            [
                "method",
                "order",
                "fps",
                "psnr",
                "temporal_instability",
                "relative_mse",
                "relative_mse_spread",
            ]
        ]
        .to_numpy()
        .tolist(),
    )
    alone = summary[summary["order"] == "none"].drop_duplicates("method")
    for row in alone.itertuples():
        spread = row.relative_mse_spread
        out.figure(f"{row.method}: relative MSE spread across the rates", spread, "x")


register(
    Benchmark(
        "frame_rate",
        "every method alone and before TAA at 30, 60, 120 and 144 fps with a 180° shutter: "
        "PSNR and temporal instability against the sequence reference, and how far its error "
        "departs from what the shutter implies",
        {
            **SEQUENCE_PARAMS,
            "scenes": Param("", str, "comma-separated scenes (empty: built-in and failure)"),
            "rates": Param("30,60,120,144", str, "comma-separated frame rates"),
        },
        _frame_rate,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (1280, 720)},
        {
            "tiny": {
                "scenes": "fan",
                "methods": ",".join(temporal.sequence_methods()[:1]),
                "rates": "30,144",
                "frames": 2,
                "warmup": 1,
                "reference_samples": 4,
            },
            "software": {"scenes": ",".join(scenes.names())},
            "gpu": {"scenes": ",".join(scenes.names()), "frames": 16, "warmup": 8},
        },
    )
)


def _sequence(ctx, size, p, out) -> None:
    method = p["method"] or next(n for n in temporal.sequence_methods() if _is_filter(n))
    names = tuple(split(p["metrics"]))
    start = time.perf_counter()
    seq = sequence(
        ctx,
        scenes.get(p["scene"]),
        size,
        frames=p["frames"],
        reference_samples=p["reference_samples"],
    )
    ctx.finish()  # the references are GPU work in flight: wait, so that each part is its own
    references = time.perf_counter()
    run = seq.run(method, "blur_then_taa", metrics=names)
    ctx.finish()
    end = time.perf_counter()
    out.figure("whole sequence: references, frames, method, TAA and metrics", end - start, "s")
    out.figure("references", references - start, "s")
    out.figure("frames, method, TAA and metrics", end - references, "s")
    out.figure("method on the GPU, mean per frame", run.blur_ms.mean(), "ms")
    out.figure("TAA on the GPU, mean per frame after the first", run.taa_ms[1:].mean(), "ms")
    for name in names:
        out.figure(f"{name} ({method} then TAA), mean", float(np.mean(run.scores[name])), "")


def _is_filter(name: str) -> bool:
    return method_info(name).kind == "filter"


register(
    Benchmark(
        "sequence",
        "a sequence with its references, three metrics and a filter then TAA, timed whole: "
        "wall seconds of each part",
        {
            "scene": Param("fan", str, "the scene"),
            "frames": Param(60, int, "frames", 2, 4096),
            "reference_samples": Param(64, int, "sub-frames of each frame's reference", 1),
            "method": Param("", str, "the method (empty: the first registered filter)"),
            "metrics": Param("psnr,ssim,temporal_instability", str, "comma-separated metrics"),
        },
        _sequence,
        {"tiny": (32, 18), "software": (320, 180), "gpu": (1920, 1080)},
        {"tiny": {"frames": 3, "reference_samples": 4}},
    )
)


def _taa_convergence(ctx, size, p, out) -> None:
    rows = []
    for name in sequence_scenes(p["scenes"]):
        scene = scenes.get(name)
        held = still(scene, sum(scene.shutter) / 2)
        seq = sequence(ctx, held, size, frames=p["frames"], reference_samples=1)
        reference = ctx.reference(
            held, size, samples=p["reference_samples"], antialias=True, progress=False
        ).color
        row = [name, metrics.psnr(reference, seq.run(None, metrics=()).color[-1])]
        for clip in TAA_PARAMS["clip"].kind:
            run = seq.run(None, "blur_then_taa", taa={"clip": clip}, metrics=())
            row.append(metrics.psnr(reference, run.color[-1]))
        row.append(100.0 * _twin_agreement(ctx, scene, size))
        rows.append(row)
    clips = TAA_PARAMS["clip"].kind
    out.table(
        f"still scenes: the last of {p['frames']} jittered frames against the antialiased "
        "reference, one frame alone and under TAA (default blend and neighbourhood) with each "
        "clip; and the TAA pass against its NumPy twin on two frames of the moving scene",
        [("scene", ""), ("one frame", "dB")]
        + [(f"TAA, clip {c}", "dB") for c in clips]
        + [("pixels within 1e-3 of the twin", "%")],
        rows,
    )
    for index, clip in enumerate(clips):
        out.figure(
            f"TAA, clip {clip}: lowest PSNR over the scenes", min(r[2 + index] for r in rows), "dB"
        )
    out.figure("TAA against its twin: lowest share within 1e-3", min(r[-1] for r in rows), "%")


def _twin_agreement(ctx, scene, size) -> float:
    """The share of pixels where the TAA pass is within 1e-3 of its twin on every channel, on
    the second frame of a two-frame sequence of `scene` (history from the first)."""
    seq = sequence(ctx, scene, size, frames=2, reference_samples=1)
    values = taa_values()
    first, second = seq.frame(0), seq.frame(1)
    motion = seq.motion_from_previous(1, second.time)
    history = taa(ctx, first.textures["color"], motion, None, **values)
    resolved = taa(ctx, second.textures["color"], motion, history, **values)
    twin = resolve(second.color, motion.download(), history.download(), **values)
    agreement = float((abs(resolved.download() - twin) <= 1e-3).all(axis=-1).mean())
    ctx.recycle(motion, history, resolved)
    return agreement


register(
    Benchmark(
        "taa_convergence",
        "TAA on still scenes: how close jittered frames come to the antialiased reference "
        "after N frames with each clip, and the TAA pass against its NumPy twin",
        {
            "scenes": Param("", str, "comma-separated scenes (empty: built-in and failure)"),
            "frames": Param(32, int, "jittered frames", 2, 4096),
            "reference_samples": Param(256, int, "sub-frames of the antialiased reference", 1),
        },
        _taa_convergence,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (1920, 1080)},
        {
            "tiny": {"scenes": "fan", "frames": 3, "reference_samples": 4},
            "software": {"scenes": ",".join(scenes.names())},
            "gpu": {"scenes": ",".join(scenes.names())},
        },
    )
)
