"""Benchmarks of what the methods get right, with their time beside: the engines side by side,
HDR scenes, the failure suite, `blurlab recommend`, real content, Blender's
cross-check, and resource use over long loops."""

from __future__ import annotations

import gc
import json
import os
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from blurlab import blender, metrics
from blurlab.blender import crosscheck
from blurlab.core.context import Context
from blurlab.methods import blur, method, method_instant, methods
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies import failures, peers
from blurlab.studies.recommend import recommend
from blurlab.studies.study import run_study
from blurlab.studies.sweep import sweep, sweep_methods

from .core import ROOT, Benchmark, Unavailable, register
from .timing import (
    film_method,
    median_passes,
    method_runs,
    optioned_filters,
    post_process_methods,
    split,
    untimed_calls_ms,
)

REFERENCES = {"temporal": "", "antialiased": peers.ANTIALIASED}
EEVEE = "eevee (Blender)"
EEVEE_POST_PROCESS = ((EEVEE, 1, 1),)  # EEVEE's real-time filter: 1 render sample, 1 step


def engine_methods() -> list[str]:
    """The engines' methods (and their peers under other names, Method.engine_peer), the
    filter that combines them (film_method), then the tile filters they are measured against."""
    engines = [n for n in methods() if n.startswith("engine_") or method(n).engine_peer]
    return engines + [film_method(), *optioned_filters()]


def _gpu_configs() -> str:
    """The engines benchmark's extra GPU rows: film_method() at 6 taps (with and without its
    film filter), and each method with tile classes in one dispatch (tile_dispatch=one)."""
    film = film_method()
    rows = [f"{film}:samples=6", f"{film}:samples=6,film_filter=0.5"]
    for name in methods():
        dispatch = method(name).params.get("tile_dispatch")
        if dispatch is not None and "one" in dispatch.kind:
            rows.append(f"{name}:tile_dispatch=one")
    return ";".join(rows)


def _engine_scene(ctx, name, size, p, runs, references) -> list[dict]:
    """Every row's pass times first, back to back, then every row's errors: reading results
    back and the CPU's metrics leave the GPU idle, and an idle GPU clocks down."""
    scene = scenes.get(name)
    # each method blurs the G-buffer at the instant it expects (docs/spec.md §3)
    instants = {method_instant(name_, params) for _, name_, params in runs}
    frames = {instant: ctx.render(scene, size, instant=instant) for instant in sorted(instants)}
    samples = p["reference_samples"] or "auto"
    rendered = {False: ctx.reference(scene, size, samples=samples, progress=False)}
    if "antialiased" in references:
        n = rendered[False].samples
        rendered[True] = ctx.reference(scene, size, samples=n, antialias=True, progress=False)
    timed = {}
    for label, name_, params in runs:
        frame = frames[method_instant(name_, params)]
        passes, _ = median_passes(ctx, frame, name_, p["runs"], **params)
        queued = untimed_calls_ms(ctx, frame, name_, **params)
        timed[label] = (passes["total"], queued, passes)
    # Metrics with a GPU implementation score on the context (within their registered
    # tolerance of NumPy's), so SSIM and FLIP at 1080p take milliseconds, not seconds.
    on_gpu = [m for m in split(p["metrics"]) if metrics.get(m).gpu is not None]
    uploaded = {}
    for reference, suffix in REFERENCES.items():
        if reference in references:
            image = np.ascontiguousarray(rendered[suffix != ""].color, np.float32)
            uploaded[suffix] = ctx.pooled(image.shape)
            uploaded[suffix].upload(image)
    rows = []
    for label, name_, params in runs:
        frame = frames[method_instant(name_, params)]
        result = blur(ctx, frame, name_, timed=False, **params)
        row = {"scene": name, "method": label, "ms": timed[label][0], "b2b_ms": timed[label][1]}
        row["passes"] = pass_rows(method(name_), result, timed[label][2])
        for suffix, reference_texture in uploaded.items():
            image = rendered[suffix != ""].color
            for m in split(p["metrics"]):
                row[m + suffix] = (
                    metrics.get(m).gpu(ctx, reference_texture, result.textures["color"])
                    if m in on_gpu
                    else peers.SCORES[m](image, result.color)
                )
        rows.append(row)
    ctx.recycle(*uploaded.values())
    if p["peers"]:
        wanted = tuple(m + REFERENCES[r] for r in references for m in split(p["metrics"]))
        rows += peers.peer_rows(
            ctx,
            name,
            scene,
            size,
            rendered.__getitem__,
            wanted,
            EEVEE_POST_PROCESS,
            p["film_filter"],
        )
    return rows


def pass_rows(m, result, medians: dict) -> list[tuple[str, str, int | None, float]]:
    """(pass, class, tiles, median ms) of each pass of a method's run: a pass dispatched over a
    tile list is timed as "pass[class]" (docs/spec.md §9.3), and where the method has tile lists
    the tiles are its list's count on this frame; a pass over every pixel has no class (nor a
    run with tile_dispatch="one", or on the fragment backend, which make no lists)."""
    counts = {}
    if m.tile_lists and "tile_counts" in result.textures:
        row = result.textures["tile_counts"].download()[0, :, 0]
        counts = dict(zip(m.tile_lists, row[::4].tolist(), strict=True))
    rows = []
    for key, ms in medians.items():
        if key == "total":
            continue
        step, _, cls = key.partition("[")
        cls = cls.rstrip("]")
        rows.append((step, cls, counts.get(cls) if cls else None, ms))
    return rows


def _engines(ctx, size, p, out) -> None:
    references = split(p["references"])
    if "temporal" not in references or set(references) - set(REFERENCES):
        raise ValueError(
            f"blurlab: engines references {p['references']!r}: names from "
            f"{', '.join(REFERENCES)}, comma-separated, temporal among them"
        )
    if p["peers"]:
        peers.check_peers([p["peers"]])
    if "psnr" not in split(p["metrics"]) or set(split(p["metrics"])) - set(peers.SCORES):
        raise ValueError(
            f"blurlab: engines metrics {p['metrics']!r}: names from {', '.join(peers.SCORES)}, "
            "comma-separated, psnr among them"
        )
    chosen = post_process_methods() if p["methods"] == "post" else split(p["methods"])
    runs = method_runs(chosen or engine_methods(), p["film_filter"], p["config"])
    names = split(p["scenes"]) or scenes.names() + scenes.names("failure")
    rows = []
    for name in names:
        rows += _engine_scene(ctx, name, size, p, runs, references)
    by_pass = [
        [row["scene"], row["method"], step, cls, tiles, ms]
        for row in rows
        for step, cls, tiles, ms in row.pop("passes", ())
    ]
    table = pd.DataFrame(rows)
    timed = table[table.method != EEVEE]
    psnrs = [m for m in ("psnr", "psnr" + peers.ANTIALIASED) if m in timed]
    medians = timed.groupby("method", sort=False)[[*psnrs, "ms", "b2b_ms"]].median()
    for label, row in medians.iterrows():
        out.figure(f"{label}: median PSNR", row.psnr, "dB")
        if "psnr" + peers.ANTIALIASED in row:
            out.figure(f"{label}: median PSNR, antialiased", row["psnr" + peers.ANTIALIASED], "dB")
        out.figure(f"{label}: median ms", row.ms, "ms")
    # the combined filter's rows (its defaults, its film filter) against each tile filter, the
    # median of the per-scene ratios of either clock
    for column, clock in (("ms", "per-pass timers"), ("b2b_ms", "calls back to back")):
        by = timed.pivot(index="scene", columns="method", values=column)
        combined = [label for label in by if label.split(",")[0] == film_method()]
        for label in combined:
            for baseline in (n for n in optioned_filters() if n in by):
                ratio = statistics.median(by[label] / by[baseline])
                out.figure(f"{label} / {baseline}, {clock} (median)", ratio, "x")
    scores = [m + REFERENCES[r] for r in references for m in split(p["metrics"])]
    columns = [("scene", ""), ("method", ""), ("per-pass timers", "ms")]
    columns.append(("calls back to back", "ms"))
    columns += [(s, "dB" if s.startswith("psnr") else "") for s in scores]
    keys = ["scene", "method", "ms", "b2b_ms", *scores]
    if "film_match_flat_db" in table:
        columns.append(("EEVEE film match, flat", "dB"))
        keys.append("film_match_flat_db")
    cells = table.reindex(columns=keys).astype(object).where(table.reindex(columns=keys).notna())
    out.table(
        "at their defaults; errors against the converged reference(s)",
        columns,
        [[None if v is None else v for v in row] for row in cells.values.tolist()],
    )
    # Where the time goes: each pass, and for a pass over tile lists each class with its tiles.
    classed = {label for _, label, _, cls, _, _ in by_pass if cls}
    passes = pd.DataFrame(by_pass, columns=["scene", "method", "pass", "class", "tiles", "ms"])
    passes = passes[passes.method.isin(classed)]
    for (label, step, cls), ms in (
        passes.groupby(["method", "pass", "class"], sort=False).ms.median().items()
    ):
        named = f"{step}[{cls}]" if cls else step
        out.figure(f"{label}: median ms, {named}", ms, "ms")
    out.table(
        "each pass of each method by tile class (per-pass timers, median ms; tiles listed)",
        [("scene", ""), ("method", ""), ("pass", ""), ("class", ""), ("tiles", ""), ("ms", "ms")],
        by_pass,
    )


register(
    Benchmark(
        "engines",
        "the engines' methods, the filter that combines them and the tile filters side by side "
        "on every built-in and failure scene: PSNR, SSIM, FLIP, ms",
        {
            "runs": Param(5, int, "timed runs per method (medians)", 1, 1000),
            "scenes": Param("", str, "comma-separated scenes (empty: built-in + failure)"),
            "methods": Param(
                "",
                str,
                "comma-separated methods (empty: the engines' set; post: every method that "
                "blurs one rendered frame)",
            ),
            "peers": Param("", ("", *peers.PEERS), "Blender's EEVEE too (needs bpy)"),
            "references": Param(
                "temporal", str, "comma-separated: temporal, antialiased (docs/spec.md §11)"
            ),
            "reference_samples": Param(0, int, "N of the references (0: from the motion)", 0),
            "metrics": Param("psnr,ssim,flip", str, "comma-separated, from psnr, ssim, flip"),
            "film_filter": Param(
                0.0, float, "σ px of an extra row with a film filter (0: none)", 0
            ),
            "config": Param("", str, "extra rows: METHOD:KEY=VALUE,... separated by ';'"),
        },
        _engines,
        {"tiny": (64, 36), "software": (160, 90), "gpu": (1920, 1080)},
        {
            "tiny": {"runs": 1, "scenes": "thin_bar", "reference_samples": 8},
            "software": {"runs": 3},
            # every method that blurs one frame, gather_coverage at 6 taps beside its 8, and the
            # methods with tile classes in one dispatch beside their lists (docs/spec.md §9.3)
            "gpu": {
                "runs": 10,
                "methods": "post",
                "references": "temporal,antialiased",
                "film_filter": 0.5,
                "config": _gpu_configs(),
            },
        },
    )
)

HDR_SCORES = ("hdr_flip", "psnr_tm", "ssim_tm", "log_lum_error", "energy_ratio")


def _hdr(ctx, size, p, out) -> None:
    names = split(p["methods"]) or sweep_methods()
    rows = []
    for scene_name in split(p["scenes"]) or scenes.names("hdr"):
        scene = scenes.get(scene_name)
        table = sweep(
            ctx,
            [scene],
            {n: {} for n in names},
            size,
            metrics=("psnr",),
            repeats=p["repeats"],
            progress=False,
        )
        timed = table.set_index("method")
        samples = int(table["reference_samples"].iloc[0])
        reference = ctx.reference(scene, size, samples=samples, progress=False).color
        for name in names:
            frame = ctx.render(scene, size, instant=method_instant(name, {}))
            image = blur(ctx, frame, name, timed=False).color
            scores = metrics.hdr_scores(reference, image)
            rows.append(
                [scene_name, name, *(scores[k] for k in HDR_SCORES)]
                + [metrics.psnr(reference, image), timed.loc[name, "total_ms"]]
            )
    frame = pd.DataFrame(rows, columns=["scene", "method", *HDR_SCORES, "psnr", "ms"])
    for name, flip in frame.groupby("method", sort=False)["hdr_flip"].median().items():
        out.figure(f"{name}: median HDR-FLIP", flip, "")
    out.table(
        "each method at its defaults; psnr clipped to [0, 1] (the LDR metric), for contrast "
        "(docs/spec.md §6.2)",
        [("scene", ""), ("method", ""), ("HDR-FLIP", ""), ("PSNR tone-mapped", "dB")]
        + [("SSIM tone-mapped", ""), ("log-luminance error", ""), ("energy ratio", "")]
        + [("PSNR clipped", "dB"), ("time", "ms")],
        rows,
    )


register(
    Benchmark(
        "hdr",
        "every single-frame method on the HDR scenes: HDR-FLIP, tone-mapped PSNR and SSIM, "
        "log-luminance error, energy ratio, ms",
        {
            "scenes": Param("", str, "comma-separated HDR scenes (empty: all)"),
            "methods": Param("", str, "comma-separated methods (empty: the sweepable ones)"),
            "repeats": Param(3, int, "timed runs per method", 1, 100),
        },
        _hdr,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (320, 180)},
        {"tiny": {"scenes": "sparks", "repeats": 1}, "software": {"repeats": 1}},
    )
)


def _failures(ctx, size, p, out) -> None:
    names = split(p["scenes"]) or None
    table = failures.evaluate(ctx, names, size=size, frames=p["frames"], progress=False)
    for name, psnr in table.groupby("method", sort=False)["psnr"].median().items():
        out.figure(f"{name}: median PSNR", psnr, "dB")
    keys = ["scene", "method", "psnr", "ssim", "nan", "inf", "outside_input_range", "flicker"]
    units = ["", "", "dB", "", "pixels", "pixels", "pixels", ""]
    shown = table[keys].astype(object).where(table[keys].notna(), None)
    out.table(
        "every single-frame method at its defaults on every failure scene",
        list(zip(keys, units, strict=True)),
        shown.values.tolist(),
    )


register(
    Benchmark(
        "failures",
        "the failure-case table: every single-frame method on every failure scene (PSNR, "
        "SSIM, NaN/Inf, out-of-range colours, flicker)",
        {
            "scenes": Param("", str, "comma-separated failure scenes (empty: all)"),
            "frames": Param(16, int, "frames of the flicker animation", 2, 1000),
        },
        _failures,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (320, 180)},
        {"tiny": {"scenes": "thin_bar", "frames": 2}},
    )
)


def _recommend(ctx, size, p, out) -> None:
    rows = []
    budgets = [float(b) for b in split(p["budgets_ms"])]
    for scene in split(p["scenes"]) or scenes.names():
        for budget in budgets:
            answer = recommend(ctx, scene, size, budget_ms=budget)
            if answer.row is None:
                rows.append([scene, budget, str(answer), None, None, None])
            else:
                row = answer.row
                label = f"{answer.method} {json.dumps(answer.params)}"
                rows.append([scene, budget, label, row["total_ms"], row["psnr"], row["ssim"]])
    for budget in budgets:
        met = [r[4] for r in rows if r[1] == budget and r[4] is not None]
        out.figure(
            f"budget {budget:g} ms: scenes answered", len(met), f"of {len(rows) // len(budgets)}"
        )
        if met:
            out.figure(
                f"budget {budget:g} ms: median PSNR of the answers", statistics.median(met), "dB"
            )
    out.table(
        "`blurlab recommend --budget-ms B` per scene",
        [("scene", ""), ("budget", "ms"), ("recommended", ""), ("time", "ms")]
        + [("PSNR", "dB"), ("SSIM", "")],
        rows,
    )


register(
    Benchmark(
        "recommend",
        "the answers of `blurlab recommend` for every built-in scene at several time budgets: "
        "each answer, its time and its error",
        {
            "scenes": Param("", str, "comma-separated scenes (empty: every built-in)"),
            "budgets_ms": Param("0.1,1,10", str, "comma-separated budgets, ms"),
        },
        _recommend,
        {"tiny": (48, 27), "software": (160, 90), "gpu": DEFAULT_SIZE},
        {"tiny": {"scenes": "fan", "budgets_ms": "10"}},
    )
)

ASSETS = ROOT.parent / "shared" / "assets" / "gltf"  # beside the checkout


def _content(ctx, size, p, out) -> None:
    folder = Path(p["assets"]) if p["assets"] else ASSETS
    models = sorted(folder.glob("*/*.gltf")) + sorted(folder.glob("*/*.glb"))
    models = [m for m in models if not p["models"] or m.stem in split(p["models"])]
    if not models:
        raise Unavailable(f"benchmark content: no glTF sample models in {folder}")
    with tempfile.TemporaryDirectory() as study_out:
        start = time.perf_counter()
        run_study(ctx, [str(m) for m in models], size=size, out=study_out, progress=False)
        out.figure("study of the models, wall", time.perf_counter() - start, "s")
        table = pd.read_csv(Path(study_out) / "results.csv")
    rows = []
    for (scene, name), group in table.groupby(["scene", "method"], sort=True):
        best = group.sort_values("psnr", ascending=False).iloc[0]
        rows.append([scene, name, best.psnr, best.ssim, best.flip, best.total_ms, best.params])
    best = pd.DataFrame(rows, columns=["scene", "method", "psnr", "ssim", "flip", "ms", "p"])
    for name, psnr in best.groupby("method")["psnr"].median().items():
        out.figure(f"{name}: median best PSNR", psnr, "dB")
    out.table(
        "the Khronos glTF sample models through the study: each method's best configuration",
        [("model", ""), ("method", ""), ("best PSNR", "dB"), ("its SSIM", "")]
        + [("its FLIP", ""), ("its time", "ms"), ("parameters", "")],
        rows,
    )


register(
    Benchmark(
        "content",
        "real content: the Khronos glTF sample models loaded, rendered and put through the "
        "study; each method's best PSNR and its time",
        {
            "assets": Param("", str, "folder of glTF models (empty: shared/assets/gltf)"),
            "models": Param("", str, "comma-separated model names (empty: all)"),
        },
        _content,
        {"tiny": (48, 27), "software": (160, 90), "gpu": DEFAULT_SIZE},
        {"tiny": {"models": "BoxAnimated"}},
    )
)


def _crosscheck(ctx, size, p, out) -> None:
    rows = []
    for name in split(p["scenes"]) or list(crosscheck.SCENES):
        scene = crosscheck.SCENES[name]()
        tracked = crosscheck.mask_scene(scene, crosscheck.TRACKED[name])
        overlaps = []
        for instant in scene.shutter:  # geometry without blur at shutter open and close
            cycles = blender.render(tracked, size, samples=p["instant_samples"], instant=instant)
            ours = ctx.reference(
                tracked, size, (instant, instant), samples=256, antialias=True, progress=False
            )
            overlaps.append(crosscheck.iou(cycles.color[..., 0], ours.color[..., 0]))
        cycles = blender.render(scene, size, samples=p["cycles_samples"], seed=0)
        n = p["reference_samples"]
        antialiased = ctx.reference(scene, size, samples=n, antialias=True, progress=False)
        temporal = ctx.reference(scene, size, samples=n, progress=False).color
        where = np.ones(temporal.shape[:2], bool)
        reference_db = crosscheck.psnr_in(antialiased.color, cycles.color, where)
        out.figure(f"{name}: antialiased reference against Cycles", reference_db, "dB")
        row = [name, min(overlaps), reference_db]
        for label, name_, params in method_runs(sweep_methods()):
            frame = ctx.render(scene, size, instant=method_instant(name_, params))
            color = blur(ctx, frame, name_, timed=False, **params).color
            rows.append(row + [label, crosscheck.psnr_in(color, cycles.color, where)])
    out.table(
        "blurlab against Blender's Cycles (docs/crosscheck.md)",
        [("scene", ""), ("geometry IoU, worst instant", ""), ("reference vs Cycles", "dB")]
        + [("method", ""), ("method vs Cycles", "dB")],
        rows,
    )


register(
    Benchmark(
        "crosscheck",
        "blurlab against Blender's Cycles: geometry at the shutter's ends, the reference and "
        "every method against Cycles (needs bpy)",
        {
            "scenes": Param("", str, "comma-separated cross-check scenes (empty: all)"),
            "cycles_samples": Param(2048, int, "Cycles samples per pixel", 1, 1 << 20),
            "instant_samples": Param(512, int, "Cycles samples of the unblurred frames", 1),
            "reference_samples": Param(1024, int, "sub-frames of blurlab's references", 1),
        },
        _crosscheck,
        {"tiny": (32, 18), "software": (160, 90), "gpu": (160, 90)},
        {
            "tiny": {
                "scenes": "box",
                "cycles_samples": 4,
                "instant_samples": 4,
                "reference_samples": 16,
            },
            "software": {"cycles_samples": 256, "instant_samples": 64, "reference_samples": 256},
        },
        needs=("bpy",),
    )
)


def _rss_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def _snapshot(ctx) -> tuple[int, float, float | None]:
    gc.collect()
    ctx.finish()
    vram = ctx.memory()
    return sum(ctx.live_objects().values()), _rss_mib(), vram["available"] / 1024 if vram else None


def _reliability(ctx, size, p, out) -> None:
    scene = scenes.teapot_pass()
    names = [n for n in methods() if not method(n).renders]

    def cycle(i):
        name = names[i % len(names)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = ctx.render(scene, size, instant=method_instant(name, {}))
            color = blur(ctx, frame, name).color
        if not np.isfinite(color).all():
            raise RuntimeError(f"blurlab: reliability: {name} gave a non-finite colour")

    for i in range(len(names)):
        cycle(i)  # every method compiled and pooled
    objects, rss, vram = _snapshot(ctx)
    start = time.perf_counter()
    for i in range(p["cycles"]):
        cycle(i)
    out.figure(
        "render + blur + readback cycle", (time.perf_counter() - start) * 1e3 / p["cycles"], "ms"
    )
    objects_after, rss_after, vram_after = _snapshot(ctx)
    out.figure("live GL objects gained over the cycles", objects_after - objects, "")
    out.figure("RSS gained over the cycles", rss_after - rss, "MiB")
    if vram is not None:
        out.figure("free video memory lost over the cycles", vram - vram_after, "MiB")
    rss = _rss_mib()
    start = time.perf_counter()
    for _ in range(p["contexts"]):
        other = Context(ctx.info()["device"])
        other.upload(np.ones((size[1], size[0], 4), np.float32)).download()
        del other
    gc.collect()
    out.figure(
        "context create + use + destroy", (time.perf_counter() - start) * 1e3 / p["contexts"], "ms"
    )
    out.figure("RSS gained over the contexts", _rss_mib() - rss, "MiB")
    out.figure("GL errors", len(ctx.gl_errors()), "")


register(
    Benchmark(
        "reliability",
        "resource use over long loops: render + blur + readback cycles and context "
        "create/destroy cycles (live GL objects, RSS, free video memory, ms each)",
        {
            "cycles": Param(1000, int, "render + blur + readback cycles", 1, 1_000_000),
            "contexts": Param(100, int, "context create/use/destroy cycles", 1, 100_000),
        },
        _reliability,
        {"tiny": (32, 18), "software": (320, 180), "gpu": (1920, 1080)},
        {"tiny": {"cycles": 4, "contexts": 2}, "software": {"cycles": 300, "contexts": 30}},
    )
)
