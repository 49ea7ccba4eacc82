"""Benchmarks of the methods' GPU time: every method, the tile filters pass by pass, the
stable filter's options, and what a Python call costs beyond its GPU work."""

from __future__ import annotations

import itertools
import statistics

import numpy as np

from blurlab import metrics
from blurlab.core.references import default_reference_samples
from blurlab.methods import (
    blur,
    coverage,
    eevee,
    method,
    method_instant,
    methods,
    plans,
    tile_filter,
)
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE

from .core import Benchmark, register
from .timing import (
    film_method,
    median_passes,
    optioned_filters,
    per_call_us,
    split,
    tile_filters,
    untimed_calls_ms,
)

RUNS = Param(10, int, "timed runs (medians over them)", 1, 10_000)
SIZES = {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)}
PASSES = ("tile_max", "neighbor_max", "reconstruct")


def _methods(ctx, size, p, out) -> None:
    scene = scenes.teapot_pass()
    rows = []
    for name in methods():  # each at its declared defaults, at the instant it declares
        instant = method_instant(name, {})
        frame = ctx.render(scene, size, instant=instant)
        blur(ctx, frame, name)  # compile, and JIT on llvmpipe
        passes, _ = median_passes(ctx, frame, name, p["runs"])
        total = passes.pop("total")
        out.figure(name, total, "ms")
        rows.append([name, instant, total, ", ".join(f"{k} {v:.4g}" for k, v in passes.items())])
    out.table(
        "each method at its defaults on teapot_pass (renders included where a method renders)",
        [("method", ""), ("instant", ""), ("total", "ms"), ("passes", "ms")],
        rows,
    )
    reference = ctx.reference(scene, size, samples=p["reference_samples"], progress=False)
    out.figure("reference per sub-frame", reference.ms_per_subframe, "ms")


register(
    Benchmark(
        "methods",
        "every registered method's ms on teapot_pass at its defaults, and the reference's ms "
        "per sub-frame",
        {
            "runs": RUNS,
            "reference_samples": Param(64, int, "sub-frames of the reference", 1, 65536),
        },
        _methods,
        SIZES,
        {"tiny": {"runs": 1, "reference_samples": 4}, "software": {"runs": 5}},
    )
)


def _filters(ctx, size, p, out) -> None:
    frame = ctx.render(scenes.teapot_pass(), size)
    rows = []
    configs = []  # (filter, label, backend, parameters): every backend, packed inputs too
    for name in tile_filters():
        configs += [(name, backend, backend, {}) for backend in method(name).backends]
        if "packed_inputs" in method(name).params:
            configs.append((name, "compute, packed inputs", None, {"packed_inputs": True}))
    totals = {}
    for name, label, backend, params in configs:
        passes, _ = median_passes(ctx, frame, name, p["runs"], backend=backend, **params)
        queued = untimed_calls_ms(ctx, frame, name, backend, **params)
        short = name.removeprefix("reconstruct_")
        totals[(name, label)] = passes["total"]
        out.figure(f"{short} {label}", passes["total"], "ms")
        out.figure(f"{short} {label}, calls back to back", queued, "ms")
        rows.append([short, label, *(passes.get(k, float("nan")) for k in PASSES)])
        rows[-1] += [passes["total"], queued]
    both = [n for n in tile_filters() if {"compute", "fragment"} <= set(method(n).backends)]
    for name in both:
        ratio = totals[(name, "fragment")] / totals[(name, "compute")]
        out.figure(f"{name.removeprefix('reconstruct_')} fragment / compute", ratio, "x")
    out.table(
        "each tile filter at its defaults (k = 20, S = 15) on teapot_pass; per-pass timers",
        [("filter", ""), ("backend", "")]
        + [(k, "ms") for k in PASSES]
        + [("total", "ms"), ("calls back to back", "ms")],
        rows,
    )
    swept = both[0]  # the first registered filter: McGuire 2012, as in the Urho3D thesis
    for title, key, values, fixed in (
        ("Table 5.2 of the Urho3D thesis: S sweep at k = 32", "samples", p["s_sweep"], {"k": 32}),
        ("Table 5.3: k sweep at S = 12", "k", p["k_sweep"], {"samples": 12}),
    ):
        rows = []
        for value in (int(v) for v in split(values)):
            params = {**fixed, key: value}
            compute, fragment = (
                median_passes(ctx, frame, swept, p["runs"], backend=b, **params)[0]["total"]
                for b in ("compute", "fragment")
            )
            rows.append([value, compute, fragment, fragment / compute])
        if rows:
            out.table(
                f"{swept}, {title}",
                [(key, ""), ("compute total", "ms"), ("fragment total", "ms"), ("ratio", "x")],
                rows,
            )


register(
    Benchmark(
        "filters",
        "the tile filters pass by pass on every backend, with packed inputs where they take "
        "them, per-pass timers and calls back to back; the Urho3D thesis's S and k sweeps",
        {
            "runs": RUNS,
            "s_sweep": Param("5,8,12,15,20,25", str, "S values at k = 32 (comma-separated)"),
            "k_sweep": Param("4,8,16,32,64", str, "k values at S = 12 (comma-separated)"),
        },
        _filters,
        SIZES,
        {
            "tiny": {"runs": 1, "s_sweep": "5", "k_sweep": "4"},
            "software": {"runs": 5},
            "gpu": {"runs": 20},
        },
    )
)

OPTIONS = {
    "": {},
    "jitter_tiles": {"jitter_tiles": 1},
    "adaptive_samples": {"adaptive_samples": 1},
    "early_exit=2": {"early_exit": 2.0},
}
BLOCKY_K = 32


def _stable_filter(ctx, size, p, out) -> None:
    filters = optioned_filters()
    configs = [(m, label, 20, o) for m in filters for label, o in OPTIONS.items()]
    configs += [
        (m, "jitter_tiles" if o else "", BLOCKY_K, o)
        for m in filters
        for o in ({}, OPTIONS["jitter_tiles"])
    ]
    rows = []
    for name in split(p["scenes"]) or scenes.names("failure") + scenes.names():
        scene = scenes.get(name)
        frame = ctx.render(scene, size)
        reference = ctx.reference(
            scene, size, samples=default_reference_samples(frame), progress=False
        )
        for m, _, k, options in configs:
            blur(ctx, frame, m, k=k, **options)  # compile before timing
        times = [[] for _ in configs]
        for _ in range(p["runs"]):  # every configuration once a round: load hits all alike
            for i, (m, _, k, options) in enumerate(configs):
                times[i].append(blur(ctx, frame, m, k=k, **options).total_ms)
        for (m, label, k, options), ms in zip(configs, times, strict=True):
            result = blur(ctx, frame, m, timed=False, k=k, **options)
            color = result.textures["color"]
            mse, ssim = metrics.gpu_mse_ssim(ctx, reference.texture, color)
            blocky = float("nan")
            if k == BLOCKY_K:
                border = metrics.tile_border_error(reference.color, result.color, BLOCKY_K, 2)
                blocky = border["ratio"]
            short = m.removeprefix("reconstruct_")
            rows.append([name, short, label, k, metrics.psnr_from_mse(mse), ssim])
            rows[-1] += [statistics.median(ms), blocky]
    for m in filters:
        short = m.removeprefix("reconstruct_")
        for label in OPTIONS:
            mine = [r for r in rows if r[1] == short and r[2] == label and r[3] == 20]
            what = f"{short}{', ' + label if label else ''}"
            out.figure(f"{what}: mean PSNR", statistics.mean(r[4] for r in mine), "dB")
            out.figure(f"{what}: mean ms", statistics.mean(r[6] for r in mine), "ms")
    out.table(
        "k = 20, S = 15, and k = 32 with the tile blockiness (error at tile borders / inside, "
        "band 2 px)",
        [("scene", ""), ("filter", ""), ("options", ""), ("k", "")]
        + [("PSNR", "dB"), ("SSIM", ""), ("time", "ms"), ("border / inside", "ratio")],
        rows,
    )


register(
    Benchmark(
        "stable_filter",
        "the tile filters with packed inputs (Guertin 2014, McGuire 2012) and each filter "
        "option on every failure and built-in scene: PSNR, SSIM, ms, tile blockiness",
        {
            "runs": Param(5, int, "timed rounds (medians)", 1, 1000),
            "scenes": Param("", str, "comma-separated scenes (empty: failure + built-in)"),
        },
        _stable_filter,
        {"tiny": (64, 36), "software": (320, 180), "gpu": (1920, 1080)},
        {"tiny": {"runs": 1, "scenes": "thin_bar"}, "software": {"runs": 3}, "gpu": {"runs": 10}},
    )
)

GRID = list(itertools.product([10, 20, 40], [5, 9, 15, 25]))  # (k, S) a sweep cycles through


def _call_overhead(ctx, size, p, out) -> None:
    scene = scenes.teapot_pass()
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=16, progress=False)
    rows = []
    for name in optioned_filters():

        def call(i, name=name):
            blur(ctx, frame, name, timed=False)

        ordinary, planned = [], []
        for _ in range(p["rounds"]):  # the two paths in turn: load hits both alike
            with plans.disabled():
                call(0)
                ordinary.append(per_call_us(ctx, call, p["calls"]))
            call(0)
            call(0)  # noted, then recorded: later calls replay the plan
            planned.append(per_call_us(ctx, call, p["calls"]))
        gpu = statistics.median(1e3 * blur(ctx, frame, name).total_ms for _ in range(p["rounds"]))
        short = name.removeprefix("reconstruct_")
        out.figure(f"{short} call, planned", min(planned), "µs")
        rows.append([short, min(ordinary), min(planned), gpu])

    swept = tile_filters()[0]

    def evaluate(i):
        k, s = GRID[i % len(GRID)]
        color = blur(ctx, frame, swept, k=k, samples=s, timed=False)
        metrics.gpu_mse_ssim(ctx, reference.texture, color.textures["color"])

    ordinary, planned = [], []
    for _ in range(p["rounds"]):
        with plans.disabled():
            ordinary.append(per_call_us(ctx, evaluate, p["calls"]))
        for i in range(len(GRID)):
            evaluate(i)
        planned.append(per_call_us(ctx, evaluate, p["calls"]))
    out.figure("sweep evaluation (blur + gpu_mse_ssim), planned", min(planned), "µs")
    rows.append(["sweep evaluation (blur + gpu_mse_ssim)", min(ordinary), min(planned), None])
    out.table(
        "wall clock per untimed call in a loop finished once (least of the rounds); dispatch "
        "plans docs/spec.md §18",
        [("call", ""), ("ordinary", "µs"), ("planned", "µs"), ("GPU clock", "µs")],
        rows,
    )


register(
    Benchmark(
        "call_overhead",
        "what a Python bl.blur call costs beyond its GPU work, with and without recorded "
        "dispatch plans, and per sweep evaluation",
        {
            "calls": Param(200, int, "calls per round", 1, 100_000),
            "rounds": Param(5, int, "rounds, the two paths in turn (least reported)", 1, 100),
        },
        _call_overhead,
        {"tiny": (16, 16), "software": (160, 90), "gpu": (1920, 1080)},
        {"tiny": {"calls": 5, "rounds": 1}, "software": {"calls": 100, "rounds": 3}},
    )
)


def layout_runs() -> list[tuple]:
    """(layout, method, parameters) of every pass with alternative layouts
    (methods.variants.PassVariants), each with a method that runs that pass."""
    return [
        (tile_filter.TILE_MAX_LAYOUT, tile_filters()[0], {}),
        (eevee.TILE_PICK_LAYOUT, film_method(), {}),
        (eevee.DILATION_LAYOUT, film_method(), {}),
        (coverage.GATHER_LAYOUT, film_method(), {}),
        (coverage.FILM_LAYOUT, film_method(), {"film_filter": FILM_SIGMA}),
    ]


FILM_SIGMA = 0.5  # px: the film filter the film layouts run with


def _layouts(ctx, size, p, out) -> None:
    rows = []
    for scene in split(p["scenes"]):
        frame = ctx.render(scenes.get(scene), size)
        for layout, name, params in layout_runs():
            default = blur(ctx, frame, name, timed=False, **params).color
            for variant in layout.variants:
                with layout.use(variant):
                    passes, _ = median_passes(ctx, frame, name, p["runs"], **params)
                    queued = untimed_calls_ms(ctx, frame, name, **params)
                    color = blur(ctx, frame, name, timed=False, **params).color
                difference = float(np.abs(color - default).max())
                label = f"{layout.what} {variant}"
                out.figure(f"{scene}, {label}: calls back to back", queued, "ms")
                out.figure(f"{scene}, {label}: largest difference from the default", difference, "")
                rows.append([scene, layout.what, variant, variant == layout.default, name])
                rows[-1] += [passes["total"], queued, difference]
    out.table(
        "each layout of a pass inside the method that runs it (the other passes at their "
        f"defaults; film filter σ = {FILM_SIGMA} px); on llvmpipe the tile passes run one thread "
        "per tile, so their work-group layouts time the same code",
        [("scene", ""), ("pass", ""), ("layout", ""), ("default", "bool"), ("method", "")]
        + [("per-pass timers", "ms"), ("calls back to back", "ms")]
        + [("largest difference from the default", "")],
        rows,
    )


register(
    Benchmark(
        "layouts",
        "every alternative layout of the passes that have them (TileMax, the tile pick and "
        "dilation, the coverage gather, the film filter): time and the image against the "
        "default layout's",
        {
            "runs": RUNS,
            "scenes": Param("teapot_pass,near_plane", str, "comma-separated scenes"),
        },
        _layouts,
        SIZES,
        {
            "tiny": {"runs": 1, "scenes": "teapot_pass"},
            "software": {"runs": 3, "scenes": "teapot_pass"},
            "gpu": {"runs": 20},
        },
    )
)
