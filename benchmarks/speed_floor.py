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
5. the G-buffer pass in steady state (after warm-up, targets from the context's pool) for each
   of --raster-scenes, against its rasterization floor on the same four float targets and a
   depth buffer (moderngl on blurlab's context): a clear + a draw that makes no fragment, a
   clear + a full-screen triangle writing constants, and the scene without shading (its
   geometry, transform only, constant outputs, then the background triangle); with triangle
   and fragment counts, and the first call on a fresh context split into shader build, mesh
   uploads, material textures, target allocation, first pass, second pass (--only-raster: this
   item alone);
6. with --study, `blurlab study` (run_study, default scenes and grids, all three metrics) at
   --size, its phases timed: references, evaluations, report (charts, images, tables).

Medians over --runs; GL timer queries on a GPU, glFinish + wall clock on llvmpipe.

    python benchmarks/speed_floor.py [--device gpu] [--size 1920x1080] [--study] [--json f]
        [--raster-scenes teapot_pass,textured_spin,vehicle] [--only-raster]
"""

from __future__ import annotations

import argparse
import importlib
import itertools
import statistics
import tempfile
import time

import numpy as np

import blurlab as bl
from blurlab import metrics
from blurlab.render import (
    camera_matrices,
    gbuffer_pass,
    instant_time,
    render_targets,
    target_shapes,
)

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


CONSTANT_FRAGMENT = """
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
TRIANGLE_VERTEX = """
#version 450
uniform bool inside;
void main() {
    // A triangle that covers the viewport at the far plane (gl_VertexID 0, 1, 2), as the
    // G-buffer's background, or one that lies outside it and makes no fragment.
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
    gl_Position = inside ? vec4(p, 1.0, 1.0) : vec4(p + 4.0, 1.0, 1.0);
}
"""
GEOMETRY_VERTEX = """
#version 450
in vec3 position;
uniform mat4 clip_from_object;
void main() { gl_Position = clip_from_object * vec4(position, 1.0); }
"""


def posed_positions(obj, time: float) -> np.ndarray:
    """The object's vertices at `time` in object space: skinned on the CPU where it has a
    skeleton (the bone matrices' weighted sum, as gbuffer.vert does), as they are otherwise."""
    mesh = obj.mesh
    if obj.skeleton is None:
        return mesh.positions
    bones = np.asarray(obj.skeleton.matrices(time), dtype=np.float64)  # (B, 4, 4)
    blend = np.einsum("vi,vixy->vxy", mesh.bone_weights, bones[mesh.bone_indices])
    p = np.concatenate([mesh.positions, np.ones((len(mesh.positions), 1))], axis=1)
    return np.einsum("vxy,vy->vx", blend, p)[:, :3].astype(np.float32)


def gbuffer_floor(ctx, scene, size: tuple[int, int], runs: int) -> dict:
    """One scene's G-buffer pass in steady state (after warm-up, targets from the pool) against
    its rasterization floor on the same four float targets and a depth buffer (moderngl on
    blurlab's context): a clear + a draw that makes no fragment; a clear + a full-screen
    triangle writing constants; the scene without shading (its geometry at the instant, drawn
    as the pass draws it but with a transform-only vertex and a constant fragment shader, then
    the background triangle where no geometry is). With triangle and fragment counts."""
    width, height = size
    shutter = scene.shutter
    instant = instant_time("center", shutter)

    def gbuffer(sides: bool):
        targets, _, timing = render_targets(ctx, scene, size, shutter, instant, sides=sides)
        ctx.recycle(*targets.values())
        return timing.ms

    record = {"scene": scene.name, "size": f"{width}x{height}"}
    for label, sides in (("gbuffer_pass_ms", False), ("gbuffer_pass_with_sides_ms", True)):
        for _ in range(3):
            gbuffer(sides)
        record[label] = statistics.median(gbuffer(sides) for _ in range(runs))

    mgl = ctx.moderngl()
    shapes = target_shapes(size)
    textures = [ctx.pooled(shape) for shape in shapes.values()]
    attachments = [mgl.external_texture(t.glo, size, t.channels, 0, "f4") for t in textures]
    depth = mgl.depth_renderbuffer(size)
    fbo = mgl.framebuffer(attachments, depth)
    depth_only = mgl.framebuffer(depth_attachment=depth)  # clears depth, not the targets
    triangle = mgl.program(vertex_shader=TRIANGLE_VERTEX, fragment_shader=CONSTANT_FRAGMENT)
    empty = mgl.vertex_array(triangle, [])
    shape_program = mgl.program(vertex_shader=GEOMETRY_VERTEX, fragment_shader=CONSTANT_FRAGMENT)
    camera = camera_matrices(scene, size, (shutter[0], shutter[1], instant))
    objects = []
    for obj in scene.objects:
        vbo = mgl.buffer(np.ascontiguousarray(posed_positions(obj, instant)).tobytes())
        ibo = mgl.buffer(obj.mesh.indices.tobytes())
        vao = mgl.vertex_array(
            shape_program, [(vbo, "3f", "position")], index_buffer=ibo, index_element_size=4
        )
        clip = camera["view_projection"][2] @ obj.model(instant)
        objects.append((vao, np.ascontiguousarray(clip.T, dtype=np.float32).tobytes()))

    def clear():
        depth_only.use()
        depth_only.clear(depth=1.0)
        fbo.use()

    def background(inside: bool):
        mgl.depth_func = "<="
        triangle["inside"].value = inside
        empty.render(vertices=3)

    def scene_geometry():
        mgl.depth_func = "<"
        for vao, clip in objects:
            shape_program["clip_from_object"].write(clip)
            vao.render()

    def draw(what: str):
        clear()
        mgl.enable(mgl.DEPTH_TEST)
        if what == "scene":
            scene_geometry()
        background(what != "empty")

    for what, key in (
        ("empty", "clear_and_empty_draw_ms"),
        ("triangle", "clear_and_fullscreen_triangle_ms"),
        ("scene", "scene_without_shading_ms"),
    ):
        record[key] = gpu_ms(ctx, lambda what=what: draw(what), runs)

    # Counts: fragments the geometry rasterizes (no depth test), those that pass the depth test
    # in the pass's draw order (shaded and written where early depth testing culls the rest),
    # and the background's (the pixels no geometry covers).
    query = mgl.query(samples=True, primitives=True)
    clear()
    mgl.disable(mgl.DEPTH_TEST)
    with query:
        scene_geometry()
    record["triangles"] = sum(len(obj.mesh.indices) for obj in scene.objects)
    record["primitives_generated"] = query.primitives
    record["fragments_rasterized"] = query.samples
    clear()
    mgl.enable(mgl.DEPTH_TEST)
    with query:
        scene_geometry()
    record["fragments_depth_passed"] = query.samples
    with query:
        background(True)
    record["background_fragments"] = query.samples
    record["pixels"] = width * height
    mgl.enable(0)
    mgl.depth_func = "<"
    # Not released: the attachments wrap blurlab's pooled textures (moderngl would delete
    # them), and moderngl rebinds the last framebuffer it used when it makes the next one (a
    # deleted one is a GL_INVALID_OPERATION there). They go with the context.
    for item in [triangle, empty, shape_program]:
        item.release()
    for vao, _ in objects:
        vao.release()
    ctx.recycle(*textures)
    ctx.make_current()
    for key in ("clear_and_empty_draw_ms", "clear_and_fullscreen_triangle_ms"):
        record[f"gbuffer_over_{key[:-3]}"] = record["gbuffer_pass_ms"] / record[key]
    record["gbuffer_over_scene_without_shading"] = (
        record["gbuffer_pass_ms"] / record["scene_without_shading_ms"]
    )
    return record


def first_call(device: str, scene, size: tuple[int, int], runs: int) -> dict:
    """Where a first G-buffer pass on a fresh context spends its time, step by step (wall clock,
    the GPU finished before and after each step): the pass's shader build (compile and link;
    llvmpipe compiles a draw's code at the first draw), the scene's mesh uploads, its material
    textures (decoded, uploaded, mip-mapped), the allocation (and first clear) of the targets,
    the first pass (by the GPU clock too), the same pass again, and the steady state; beside
    it, the whole first ctx.render on another fresh context."""
    record = {}
    whole = open_context(device)
    whole.finish()
    start = time.perf_counter()
    frame = whole.render(scene, size)
    record["first_render_call_wall_ms"] = 1e3 * (time.perf_counter() - start)
    record["first_render_call_gbuffer_ms"] = frame.timings["gbuffer"].ms
    del frame, whole

    ctx = open_context(device)
    shutter = scene.shutter
    instant = instant_time("center", shutter)

    def step(fn):
        ctx.finish()
        begin = time.perf_counter()
        result = fn()
        ctx.finish()
        return 1e3 * (time.perf_counter() - begin), result

    record["shader_build_ms"], _ = step(lambda: gbuffer_pass(ctx))
    record["mesh_upload_ms"], _ = step(lambda: [ctx.gpu_mesh(o.mesh) for o in scene.objects])
    record["material_texture_upload_ms"], _ = step(
        lambda: [ctx.gpu_material_texture(o.material) for o in scene.objects]
    )
    shapes = target_shapes(size, sides=True)
    record["target_allocation_ms"], textures = step(
        lambda: [ctx.pooled(shape) for shape in shapes.values()]
    )
    ctx.recycle(*textures)
    for label in ("first_pass", "second_pass"):
        wall, (targets, _, timing) = step(
            lambda: render_targets(ctx, scene, size, shutter, instant, sides=True)
        )
        ctx.recycle(*targets.values())
        record[f"{label}_wall_ms"], record[f"{label}_gbuffer_ms"] = wall, timing.ms
    steady = []
    for _ in range(runs):
        targets, _, timing = render_targets(ctx, scene, size, shutter, instant, sides=True)
        ctx.recycle(*targets.values())
        steady.append(timing.ms)
    record["steady_gbuffer_ms"] = statistics.median(steady)
    return record


def raster_floor(device: str, ctx, scene_names, size: tuple[int, int], runs: int) -> dict:
    """gbuffer_floor and first_call for each of `scene_names`, printed as two tables."""
    record = {name: {} for name in scene_names}
    for name in scene_names:
        record[name]["steady"] = gbuffer_floor(ctx, bl.scenes.get(name), size, runs)
    for name in scene_names:
        record[name]["first_call"] = first_call(device, bl.scenes.get(name), size, runs)
    w, h = size
    print(f"\n| G-buffer at {w}x{h}, ms | " + " | ".join(scene_names) + " |")
    print("|---|" + "---|" * len(scene_names))
    rows = [
        ("triangles", "triangles", "{:d}"),
        ("fragments rasterized (geometry)", "fragments_rasterized", "{:d}"),
        ("fragments passing depth (geometry)", "fragments_depth_passed", "{:d}"),
        ("background fragments", "background_fragments", "{:d}"),
        ("G-buffer pass, 4 targets (as references)", "gbuffer_pass_ms", "{:.4f}"),
        ("G-buffer pass, 5 targets (as ctx.render)", "gbuffer_pass_with_sides_ms", "{:.4f}"),
        ("clear + empty draw", "clear_and_empty_draw_ms", "{:.4f}"),
        ("clear + full-screen triangle", "clear_and_fullscreen_triangle_ms", "{:.4f}"),
        ("scene without shading", "scene_without_shading_ms", "{:.4f}"),
        ("G-buffer / scene without shading", "gbuffer_over_scene_without_shading", "{:.2f}x"),
    ]
    for label, key, fmt in rows:
        cells = [fmt.format(record[n]["steady"][key]) for n in scene_names]
        print(f"| {label} | " + " | ".join(cells) + " |")
    print(f"\n| first G-buffer pass on a fresh context, {w}x{h}, ms | " + " | ".join(scene_names))
    print("|---|" + "---|" * len(scene_names))
    for key in record[scene_names[0]]["first_call"]:
        cells = [f"{record[n]['first_call'][key]:.3f}" for n in scene_names]
        print(f"| {key} | " + " | ".join(cells) + " |")
    return record


def study_phases(ctx, size: tuple[int, int]) -> dict:
    """run_study at `size`, default scenes and grids, PSNR + SSIM + FLIP, with its phases:
    references (every ctx.reference call), evaluations (the sweep less its references) and the
    report (the rest: charts, images, per-object table, HTML)."""
    study = importlib.import_module("blurlab.studies.study")
    phases = {"references": 0.0, "references_in_sweep": 0.0, "sweep": 0.0}
    in_sweep = [False]
    reference, sweep = ctx.reference, study.sweep

    def timed_reference(*args, **kwargs):
        start = time.perf_counter()
        try:
            return reference(*args, **kwargs)
        finally:
            spent = time.perf_counter() - start
            phases["references"] += spent
            if in_sweep[0]:
                phases["references_in_sweep"] += spent

    def timed_sweep(*args, **kwargs):
        start, in_sweep[0] = time.perf_counter(), True
        try:
            return sweep(*args, **kwargs)
        finally:
            phases["sweep"] += time.perf_counter() - start
            in_sweep[0] = False

    ctx.reference, study.sweep = timed_reference, timed_sweep
    try:
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            study.run_study(ctx, size=size, out=folder, progress=False)
            total = time.perf_counter() - start
    finally:
        del ctx.reference
        study.sweep = sweep
    record = {
        "total_s": total,
        "references_s": phases["references"],
        "evaluations_s": phases["sweep"] - phases["references_in_sweep"],
        "report_s": total
        - phases["sweep"]
        - (phases["references"] - phases["references_in_sweep"]),
    }
    print(f"\n| study at {size[0]}x{size[1]}, phase | s |\n|---|---|")
    for key, value in record.items():
        print(f"| {key} | {value:.1f} |")
    return record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--evaluations", type=int, default=500)
    parser.add_argument("--bandwidth-size", default="4096x4096")
    parser.add_argument("--nominal-gbs", type=float, default=None, help="e.g. 3350 (H100 SXM)")
    parser.add_argument("--study", action="store_true", help="also time blurlab study")
    parser.add_argument(
        "--raster-scenes",
        default="teapot_pass,textured_spin,vehicle",
        help="scenes of the G-buffer floor (comma-separated)",
    )
    parser.add_argument(
        "--only-raster", action="store_true", help="only the G-buffer floor (item 5)"
    )
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, medians of {args.runs} runs")
    if not args.only_raster:
        measure_filters_and_metrics(ctx, size, args, record)
    save(args.json, record)  # before the moderngl part, which shares the GL context
    try:
        record["raster"] = raster_floor(
            args.device, ctx, args.raster_scenes.split(","), size, args.runs
        )
    except ImportError as error:  # moderngl is not on every machine that measures
        print(f"\nrasterization floor left out: {error}")
    save(args.json, record)


def measure_filters_and_metrics(ctx, size: tuple[int, int], args, record: dict) -> None:
    """Items 1 to 4 and 6 of the module's list, on teapot_pass."""
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=64, progress=False)
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


if __name__ == "__main__":
    main()
