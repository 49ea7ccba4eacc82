"""Issue 19's figures in one run ("speed to the floor"), on one G-buffer of teapot_pass:

1. filters: McGuire 2012 (k = 20, S = 15) and Guertin 2014 per pass, compute and fragment
   (fragment / compute), and a Python call (wall clock per bl.blur over a loop, finished once)
   against its GPU time;
2. bytes per pixel the filter cannot avoid (read colour, depth and motion once, write colour
   once, as the textures are stored) and the share of the DRAM floor: those bytes at the
   bandwidth of a streaming pass (accumulate.comp over --bandwidth-size, 48 B per pixel)
   against the filter's GPU time;
3. sweep evaluations per second (blur + metrics reduced on the GPU, untimed, parameters
   cycling through k and S) with PSNR + SSIM and with PSNR + SSIM + FLIP;
4. gpu_ssim, gpu_flip and gpu_mse: wall clock per call (with the scalar read back) and GPU time;
5. the G-buffer pass against the rasterization floor on the same four float targets and depth
   buffer (moderngl on blurlab's context): a draw that makes no fragment, and a full-screen
   triangle writing constants;
6. with --study, `blurlab study` (run_study, default scenes and grids, all three metrics) at
   --size, with the phases it times itself (phases.json): references, G-buffers, evaluations,
   images, charts, per-object table, HTML.

Medians over --runs; GL timer queries on a GPU, glFinish + wall clock on llvmpipe.

    python benchmarks/speed_floor.py [--device gpu] [--size 1920x1080] [--study] [--json f]
"""

from __future__ import annotations

import argparse
import importlib
import itertools
import json
import statistics
import tempfile
import time
from pathlib import Path

import blurlab as bl
from blurlab import metrics

from common import describe, open_context, save

FILTERS = {
    "reconstruct_mcguire2012": {"k": 20, "samples": 15},
    "reconstruct_guertin2014": {},
}


def gpu_ms(ctx, fn, runs: int) -> float:
    """Median GPU time of fn() by the context's clock."""
    fn()
    samples = []
    for _ in range(runs):
        with ctx.timer() as timing:
            fn()
        samples.append(timing.ms)
    return statistics.median(samples)


def wall_ms(fn, runs: int) -> float:
    fn()
    samples = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        samples.append(1e3 * (time.perf_counter() - start))
    return statistics.median(samples)


def filters(ctx, frame, runs: int) -> dict:
    out = {}
    print("\n| filter / backend | per pass, ms | GPU total, ms | Python call, ms | call / GPU |")
    print("|---|---|---|---|---|")
    for name, params in FILTERS.items():
        out[name] = {}
        for backend in bl.method(name).backends:
            for _ in range(2):
                bl.blur(ctx, frame, name, backend=backend, **params)
            per_pass: dict = {}
            for _ in range(runs):
                result = bl.blur(ctx, frame, name, backend=backend, **params)
                for p, t in result.timings.items():
                    per_pass.setdefault(p, []).append(t.ms)
                del result
            medians = {p: statistics.median(v) for p, v in per_pass.items()}
            total = sum(medians.values())
            # A Python call as a sweep makes it: untimed, the GPU finished once after the loop.
            calls = max(runs, 20)
            ctx.finish()
            start = time.perf_counter()
            for _ in range(calls):
                bl.blur(ctx, frame, name, backend=backend, timed=False, **params)
            ctx.finish()
            call = 1e3 * (time.perf_counter() - start) / calls
            out[name][backend] = {"passes_ms": medians, "total_ms": total, "call_ms": call}
            passes = ", ".join(f"{p} {v:.4f}" for p, v in medians.items())
            print(
                f"| {name} / {backend} | {passes} | {total:.4f} | {call:.4f} | {call / total:.2f} |"
            )
        both = out[name]
        if "fragment" in both:
            both["fragment_over_compute"] = (
                both["fragment"]["total_ms"] / both["compute"]["total_ms"]
            )
            print(f"| {name}: fragment / compute | | {both['fragment_over_compute']:.1f}x | | |")
    return out


def streaming_bandwidth(ctx, size: tuple[int, int], runs: int) -> dict:
    """Bytes per second of accumulate.comp (reads a colour and a sum, writes the sum: 3 RGBA32F
    texels, 48 B per pixel) over images too large for the caches."""
    width, height = size
    color = ctx.empty((height, width, 4))
    total = ctx.empty((height, width, 4))
    step = ctx.shader_pass("passes/accumulate.comp")
    ms = gpu_ms(ctx, lambda: step.run({"color": color}, {"sum": total}, {"weight": 0.5}), runs)
    ctx.recycle(color, total)
    return {"size": f"{width}x{height}", "ms": ms, "gb_per_s": 48 * width * height / ms / 1e6}


def dram_floor(ctx, frame, filter_results: dict, bandwidth: dict, nominal_gbs) -> dict:
    textures = frame.textures
    stored = {
        k: textures[k].dtype.itemsize * textures[k].channels for k in ("color", "depth", "motion")
    }
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False)
    out_texture = result.textures["color"]
    stored["output colour"] = out_texture.dtype.itemsize * out_texture.channels
    per_pixel = sum(stored.values())
    pixels = frame.color.shape[0] * frame.color.shape[1]
    record = {"bytes_per_pixel": stored, "total_bytes_per_pixel": per_pixel, "filters": {}}
    rates = {"measured streaming": bandwidth["gb_per_s"]}
    if nominal_gbs:
        rates["nominal"] = nominal_gbs
    print(f"\nBytes per pixel the filter cannot avoid, as stored: {stored} = {per_pixel} B")
    print(f"Streaming pass: {bandwidth['gb_per_s']:.0f} GB/s over {bandwidth['size']}\n")
    print("| filter | bandwidth | DRAM floor, ms | filter GPU, ms | floor / filter |")
    print("|---|---|---|---|---|")
    for name, backends in filter_results.items():
        gpu = backends["compute"]["total_ms"]
        for label, gbs in rates.items():
            floor = per_pixel * pixels / (gbs * 1e6)
            record["filters"][f"{name} ({label})"] = {
                "floor_ms": floor,
                "filter_ms": gpu,
                "share": floor / gpu,
            }
            print(
                f"| {name} | {label} {gbs:.0f} GB/s | {floor:.4f} | {gpu:.4f} | {floor / gpu:.0%} |"
            )
    return record


def sweep_rate(ctx, frame, reference, evaluations: int) -> dict:
    grid = list(itertools.product([10, 20, 40], [5, 9, 15, 25]))
    record = {}
    print("\n| sweep, untimed, reconstruct_mcguire2012 | evaluations / s | ms per evaluation |")
    print("|---|---|---|")
    for label, chosen in (("PSNR + SSIM", ("ssim",)), ("PSNR + SSIM + FLIP", ("ssim", "flip"))):

        def evaluate(i, chosen=chosen):
            k, s = grid[i % len(grid)]
            result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=False)
            color = result.textures["color"]
            row = {"psnr": metrics.psnr_from_mse(metrics.gpu_mse(ctx, color, reference.texture))}
            if "ssim" in chosen:
                row["ssim"] = metrics.gpu_ssim(ctx, reference.texture, color)
            if "flip" in chosen:
                row["flip"] = metrics.gpu_flip(ctx, reference.texture, color)
            return row

        for i in range(3):
            evaluate(i)
        start = time.perf_counter()
        for i in range(evaluations):
            row = evaluate(i)
        rate = evaluations / (time.perf_counter() - start)
        record[label] = {"evaluations_per_s": rate, "last_row": row}
        print(f"| {label} | {rate:.0f} | {1e3 / rate:.3f} |")
    return record


def metric_times(ctx, frame, reference, runs: int) -> dict:
    color = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False).textures["color"]
    ways = {
        "gpu_mse": lambda: metrics.gpu_mse(ctx, color, reference.texture),
        "gpu_ssim": lambda: metrics.gpu_ssim(ctx, reference.texture, color),
        "gpu_flip": lambda: metrics.gpu_flip(ctx, reference.texture, color),
    }
    record = {}
    print("\n| metric, one image pair | wall ms per call | GPU ms | value |\n|---|---|---|---|")
    for name, fn in ways.items():
        value = fn()
        record[name] = {"wall_ms": wall_ms(fn, runs), "gpu_ms": gpu_ms(ctx, fn, runs)}
        record[name]["value"] = value
        r = record[name]
        print(f"| {name} | {r['wall_ms']:.4f} | {r['gpu_ms']:.4f} | {value:.6f} |")
    return record


RASTER_VERTEX = """
#version 450
uniform float depth;
void main() {
    // A triangle that covers the viewport (gl_VertexID 0, 1, 2), or one point (depth < 0).
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
    gl_Position = depth < 0.0 ? vec4(2.0, 2.0, 0.5, 1.0) : vec4(p, depth, 1.0);
}
"""
RASTER_FRAGMENT = """
#version 450
layout(location = 0) out vec4 color;
layout(location = 1) out float depth_out;
layout(location = 2) out vec2 motion;
layout(location = 3) out float object_id;
void main() {
    color = vec4(0.5);
    depth_out = 1.0;
    motion = vec2(0.25);
    object_id = 1.0;
}
"""


def raster_floor(ctx, scene, size: tuple[int, int], runs: int) -> dict:
    """The G-buffer pass against draws on the same targets (RGBA32F colour, R32F depth, RG32F
    motion, R32F object id, a depth buffer): one that makes no fragment, and a full-screen
    triangle that writes constants."""
    width, height = size
    frames = [ctx.render(scene, size) for _ in range(runs + 1)][1:]
    gbuffer = statistics.median(f.timings["gbuffer"].ms for f in frames)
    mgl = ctx.moderngl()
    targets = [
        mgl.texture(size, 4, dtype="f4"),
        mgl.texture(size, 1, dtype="f4"),
        mgl.texture(size, 2, dtype="f4"),
        mgl.texture(size, 1, dtype="f4"),
    ]
    fbo = mgl.framebuffer(targets, mgl.depth_renderbuffer(size))
    program = mgl.program(vertex_shader=RASTER_VERTEX, fragment_shader=RASTER_FRAGMENT)
    vao = mgl.vertex_array(program, [])

    def draw(depth: float):
        fbo.use()
        mgl.enable(mgl.DEPTH_TEST)
        fbo.clear(depth=1.0)
        program["depth"].value = depth
        vao.render(vertices=3)

    record = {
        "gbuffer_pass_ms": gbuffer,
        "clear_and_empty_draw_ms": gpu_ms(ctx, lambda: draw(-1.0), runs),
        "clear_and_fullscreen_triangle_ms": gpu_ms(ctx, lambda: draw(0.0), runs),
    }
    mgl.enable(0)
    for texture in targets:
        texture.release()
    fbo.release()
    floor = record["clear_and_fullscreen_triangle_ms"]
    record["gbuffer_over_fullscreen"] = gbuffer / floor
    print(f"\n| rasterization, {width}x{height}, 4 float targets + depth | ms |\n|---|---|")
    for key, value in record.items():
        print(f"| {key} | {value:.4f} |")
    return record


def study_phases(ctx, size: tuple[int, int]) -> dict:
    """run_study at `size`, default scenes and grids, PSNR + SSIM + FLIP, and the phases it
    times itself (phases.json: references, G-buffers, evaluations, images, charts, per-object
    table, HTML), with the process's CPU time beside the wall clock."""
    study = importlib.import_module("blurlab.studies.study")
    with tempfile.TemporaryDirectory() as folder:
        start, cpu = time.perf_counter(), time.process_time()
        study.run_study(ctx, size=size, out=folder, progress=False)
        total, cpu = time.perf_counter() - start, time.process_time() - cpu
        timing = json.loads((Path(folder) / "phases.json").read_text())
    record = {"total_s": total, "cpu_s": cpu}
    record.update({f"{phase}_s": seconds for phase, seconds in timing["phases_s"].items()})
    print(f"\n| study at {size[0]}x{size[1]}, {timing['evaluations']} evaluations | s |\n|---|---|")
    for key, value in record.items():
        print(f"| {key} | {value:.1f} |")
    return {**record, "evaluations": timing["evaluations"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--evaluations", type=int, default=500)
    parser.add_argument("--bandwidth-size", default="4096x4096")
    parser.add_argument("--nominal-gbs", type=float, default=None, help="e.g. 3350 (H100 SXM)")
    parser.add_argument("--study", action="store_true", help="also time blurlab study")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=64, progress=False)
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, medians of {args.runs} runs")
    record["filters"] = filters(ctx, frame, args.runs)
    bandwidth_size = tuple(int(v) for v in args.bandwidth_size.split("x"))
    record["bandwidth"] = streaming_bandwidth(ctx, bandwidth_size, args.runs)
    record["dram_floor"] = dram_floor(
        ctx, frame, record["filters"], record["bandwidth"], args.nominal_gbs
    )
    record["sweep"] = sweep_rate(ctx, frame, reference, args.evaluations)
    record["metrics"] = metric_times(ctx, frame, reference, args.runs)
    if args.study:
        record["study"] = study_phases(ctx, size)
    save(args.json, record)  # before the moderngl part, which shares the GL context
    try:
        record["raster"] = raster_floor(ctx, scene, size, args.runs)
    except ImportError as error:  # moderngl is not on every machine that measures
        print(f"\nrasterization floor left out: {error}")
    save(args.json, record)


if __name__ == "__main__":
    main()
