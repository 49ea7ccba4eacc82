"""Benchmarks of getting a frame in and out: transfers, the G-buffer pass, hatching, the
reference loop and the motion storage formats."""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

from blurlab.core.frame import MOTION_FORMATS
from blurlab.core.render import stored_motion
from blurlab.hatching import patterns as hatching_schemes
from blurlab.hatching import tam
from blurlab.methods.params import Param
from blurlab.scene import scenes
from blurlab.sizes import DEFAULT_SIZE
from blurlab.studies import hatching

from .core import Benchmark, register
from .timing import per_call_us, split, wall_ms

RUNS = Param(20, int, "timed runs (medians over them)", 1, 10_000)
SCENE = Param("teapot_pass", tuple(scenes.names()), "the built-in scene")


def _transfer(ctx, size, p, out) -> None:
    width, height = size
    image = np.random.default_rng(0).random((height, width, 4), dtype=np.float32)
    megabytes = image.nbytes / 1e6
    texture = ctx.upload(image)
    ctx.finish()
    if not np.array_equal(texture.download(), image):  # the paths move the real data
        raise RuntimeError("blurlab: transfer: the downloaded image is not the uploaded one")

    def upload():
        texture.upload(image)
        ctx.finish()

    def pipelined() -> list[float]:
        """Per-image ms with `depth` downloads kept in flight."""
        in_flight = [texture.download_async() for _ in range(p["depth"])]
        start = time.perf_counter()
        for _ in range(p["runs"]):
            in_flight.pop(0).result()
            in_flight.append(texture.download_async())
        for pending in in_flight:
            pending.result()
        return [(time.perf_counter() - start) * 1e3 / (p["runs"] + p["depth"])]

    paths = {
        "upload": wall_ms(upload, p["runs"]),
        "download": wall_ms(texture.download, p["runs"]),
        "download async": pipelined(),
    }
    # Untimed: the same pipeline, each image compared with the uploaded one (docs/foundation.md
    # names a fault of this path on the H100).
    in_flight = [texture.download_async() for _ in range(p["depth"])]
    differing = 0
    for i in range(p["runs"] + p["depth"]):
        differing += not np.array_equal(in_flight.pop(0).result(), image)
        if i < p["runs"]:
            in_flight.append(texture.download_async())
    out.figure("async downloads unlike the uploaded image", differing, "images")
    rows = []
    for path, samples in paths.items():
        median = statistics.median(samples)
        out.figure(f"{path} GB/s", megabytes / median, "GB/s")
        rows.append([path, median, megabytes / median, megabytes / min(samples)])
    out.table(
        f"RGBA float32, {megabytes:.1f} MB; wall clock, glFinish included",
        [("path", ""), ("median", "ms"), ("median", "GB/s"), ("best", "GB/s")],
        rows,
    )


register(
    Benchmark(
        "transfer",
        "upload and download throughput of an RGBA float32 image: sync, and async with "
        "downloads in flight",
        {"runs": RUNS, "depth": Param(3, int, "async downloads in flight", 1, 64)},
        _transfer,
        {"tiny": (64, 36), "software": (1920, 1080), "gpu": (1920, 1080)},
        {"tiny": {"runs": 2}},
    )
)


def _gbuffer(ctx, size, p, out) -> None:
    scene = scenes.get(p["scene"])
    for _ in range(2):
        ctx.render(scene, size)  # compile (llvmpipe JIT-compiles each variant) and warm up
    passes, calls, read = [], [], []
    for _ in range(p["runs"]):
        start = time.perf_counter()
        frame = ctx.render(scene, size)
        ctx.finish()  # the call returns before the GPU is done (docs/spec.md §1.1)
        calls.append((time.perf_counter() - start) * 1e3)
        passes.append(frame.timings["gbuffer"].ms)
        for field in ("color", "depth", "motion", "object_id"):
            getattr(frame, field)  # each downloaded when first read
        read.append((time.perf_counter() - start) * 1e3)
    # Back to back, as a loop that reads no field issues them, each frame dropped before the
    # next (its textures go back to the pool): the wall time per call.
    start = time.perf_counter()
    for _ in range(p["runs"]):
        ctx.render(scene, size)
    ctx.finish()
    back_to_back = (time.perf_counter() - start) * 1e3 / p["runs"]
    pass_ms = statistics.median(passes)
    out.figure("G-buffer pass", pass_ms, "ms")
    out.figure(
        "ctx.render call and the GPU's work, no field read (wall)", statistics.median(calls), "ms"
    )
    out.figure("ctx.render calls back to back, no field read (wall, each)", back_to_back, "ms")
    out.figure("ctx.render call, its four fields read (wall)", statistics.median(read), "ms")
    out.figure("one call and the GPU's work over the pass", statistics.median(calls) / pass_ms, "x")
    out.figure("back-to-back calls over the pass", back_to_back / pass_ms, "x")
    out.figure("triangles", sum(len(o.mesh.indices) for o in scene.objects), "")


register(
    Benchmark(
        "gbuffer",
        "the G-buffer pass of a scene, and ctx.render as a Python caller sees it",
        {"scene": SCENE, "runs": RUNS},
        _gbuffer,
        {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {"tiny": {"runs": 2}},
    )
)


def _hatching(ctx, size, p, out) -> None:
    texture_map = tam.default_tam()
    for name in ("lambert", *hatching_schemes.SCHEMES):
        scene = hatching.pair_scene(None if name == "lambert" else name, texture_map)
        for _ in range(2):
            ctx.render(scene, size)  # shader compilation
        times = [ctx.render(scene, size).timings["gbuffer"].ms for _ in range(p["runs"])]
        out.figure(f"{name} G-buffer pass", statistics.median(times), "ms")
    if not p["measure"]:
        return
    rows = []
    for scheme in hatching_schemes.SCHEMES:
        tone = hatching.tone_reproduction(ctx, scheme, texture_map, steps=64, size=256)
        moving = hatching.temporal_coherence(ctx, scheme, texture_map, frames=p["frames"])
        still = hatching.temporal_coherence(
            ctx, scheme, texture_map, frames=p["frames"], moving_light=False
        )
        rows.append(
            [
                scheme,
                tone["mean_abs_error"],
                tone["distinguishable_steps"],
                moving["mean_pop_fraction"],
                still["mean_pop_fraction"],
                moving["mean_reprojected_pop_fraction"],
                moving["mean_ink_change"],
            ]
        )
    out.table(
        "tone reproduction (64 tones) and temporal coherence",
        [
            ("scheme", ""),
            ("tone error", "mean abs"),
            ("distinguishable steps", "of 64"),
            ("pops, moving light", "fraction"),
            ("pops, still light", "fraction"),
            ("pops reprojected, moving light", "fraction"),
            ("ink change, moving light", "mean abs"),
        ],
        rows,
    )


register(
    Benchmark(
        "hatching",
        "the two hatching schemes' G-buffer pass beside Lambert shading (teapot + torus), "
        "and their tone reproduction and temporal coherence",
        {
            "runs": RUNS,
            "measure": Param(True, bool, "also measure tone reproduction and coherence"),
            "frames": Param(32, int, "frames of the temporal-coherence animation", 2, 1000),
        },
        _hatching,
        {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {"tiny": {"runs": 1, "measure": False}, "software": {"runs": 5, "frames": 16}},
    )
)


def _reference_loop(ctx, size, p, out) -> None:
    rows = []
    for name in split(p["scenes"]):
        scene = scenes.get(name)
        ctx.reference(scene, size, samples=4, progress=False)  # programs, meshes
        walls, gpus = [], []
        for _ in range(p["runs"]):

            def reference(i, scene=scene, gpus=gpus):
                made = ctx.reference(scene, size, samples=p["samples"], progress=False)
                gpus.append(1e3 * made.ms_per_subframe)

            walls.append(per_call_us(ctx, reference, 1) / p["samples"])
        wall, gpu = statistics.median(walls), statistics.median(gpus)
        out.figure(f"{name} wall per sub-frame", wall, "µs")
        rows.append([name, wall, gpu])
    out.table(
        f"ctx.reference, N = {p['samples']}",
        [("scene", ""), ("wall per sub-frame", "µs"), ("GPU clock per sub-frame", "µs")],
        rows,
    )


register(
    Benchmark(
        "reference_loop",
        "the reference's sub-frames: wall clock of ctx.reference per sub-frame beside the GPU "
        "time it reports",
        {
            "scenes": Param("teapot_pass,vehicle", str, "comma-separated built-in scenes"),
            "samples": Param(256, int, "sub-frames of each reference", 1, 65536),
            "runs": Param(3, int, "references per scene (medians)", 1, 1000),
        },
        _reference_loop,
        {"tiny": (64, 36), "software": DEFAULT_SIZE, "gpu": (1920, 1080)},
        {"tiny": {"scenes": "teapot_pass", "samples": 4, "runs": 1}, "software": {"samples": 64}},
    )
)

LENGTHS = (0.1, 0.25, 0.5, 1, 2, 4, 8, 16, 32, 64)


def _motion_formats(ctx, size, p, out) -> None:
    rng = np.random.default_rng(0)
    count = p["vectors"]
    angles = np.linspace(0, 2 * np.pi, count, endpoint=False) + rng.uniform(0, 1e-3, count)
    directions = np.stack([np.cos(angles), np.sin(angles)], -1)
    motion = np.stack([directions * length for length in LENGTHS]).astype(np.float32)
    formats = MOTION_FORMATS[1:]  # against the first, rg32f
    decoded = {f: stored_motion(ctx, motion, f, p["maxlen"]) for f in formats}
    rows = []
    for row, length in enumerate(LENGTHS):
        cells = [length]
        for fmt in formats:
            error = np.linalg.norm(decoded[fmt][row] - motion[row], axis=-1)
            cells += [float(error.mean()), float(error.max())]
        rows.append(cells)
    for i, fmt in enumerate(formats):
        out.figure(f"{fmt} largest error at |M| = {LENGTHS[-1]} px", rows[-1][2 + 2 * i], "px")
    columns = [("|M|", "px")]
    for fmt in formats:
        columns += [(f"{fmt} mean", "px"), (f"{fmt} max", "px")]
    out.table(f"decoded against stored, maxlen {p['maxlen']:.1f} px", columns, rows)


register(
    Benchmark(
        "motion_formats",
        "error of each motion storage format against rg32f as the motion grows (docs/spec.md "
        "§2), on the GPU's encode/decode pass",
        {
            "maxlen": Param(
                math.hypot(1920, 1080), float, "the formats' maxlen, px", 0, None, low_open=True
            ),
            "vectors": Param(4096, int, "vectors of each length, evenly spread", 1, 1 << 20),
        },
        _motion_formats,
        None,
        {"tiny": {"vectors": 64}},
    )
)
