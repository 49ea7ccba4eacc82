"""Where the time of the tile filters and of gather_coverage goes on one context (issue 19: the
filter goals; issue 17: gather_coverage's time against guertin2014's), on one G-buffer of
teapot_pass (or --scene), in six parts.

1. ``passes``: McGuire 2012 (k = 20, S = 15) and Guertin 2014, with stored and with packed
   inputs (docs/spec.md §19), and gather_coverage without and with film_filter = 0.5 (and with
   the dilation by gather instead of scatter, methods.eevee.DILATION_VARIANTS) are each run
   once with their passes recorded (blurlab.methods.plans.Recorder); the recorded passes are
   then replayed, each pass alone and each prefix of them (the first pass, the first two,
   ...), 50 times back to back behind busy work (common.back_to_back_ms). So what a pass costs
   on its own and what the pass boundaries add (the GPU drains before a dependent pass) can be
   told apart. Beside them: a pass over one texel, back to back (what any dispatch costs), and
   gather_coverage's film pass reading the gather's image as RGBA16F instead of RGBA32F. (The
   first version of this file, in git history, also timed the reconstruct passes built with
   their sample count as a compile-time constant: docs/benchmarks.md gives what it measured.)
2. ``fetch``: whether the reconstruct pass's taps, or its own reads and write, hold it. The
   same gather as McGuire's reconstruct (S taps along the tile's NeighborMax, jittered per
   pixel, McGuire's weights, an early exit at McGuire's |vN| <= 0.51 px), written once here over
   teapot_pass's inputs rounded to halves, with a NeighborMax grid computed in NumPy from
   the unclamped half-motions (so |vN| is up to 3.5x k on this scene), read through:
   - ``two_textures``: colour and motion + depth from two RGBA16F textures (today's packed path);
   - ``one_texture``: one RGBA32UI texel a pixel (colour as four halves, motion as two, depth as
     one; unpackHalf2x16), one fetch a tap;
   - ``buffer_rows``: the same 16 bytes a pixel in a storage buffer, row by row (one 128-bit
     load a tap through the load/store path, not the texture units);
   - ``buffer_blocks``: the same in 8 x 8 pixel blocks, for 2D locality;
   - ``two_textures_half_out``: today's path writing RGBA16F instead of RGBA32F;
   - ``two_textures_runtime_samples``, ``_pcg``: the sample count a uniform (the loop cannot
     unroll) and the filters' own hash for the jitter, as the real pass has them;
   - ``two_textures_no_jitter``, ``buffer_rows_no_jitter``: every pixel's taps at the same
     offsets along vN, so neighbouring invocations read neighbouring texels;
   - ``centre_only`` (and ``_one_texture``, ``_buffer_rows``): each pixel's own texels read and
     its result written, no tap: the pass's floor.
   Every variant with taps must give the same image as its kin (``two_textures``, or the one
   with the same hash or jitter; the record says so). moderngl on blurlab's context.
   ``fetch_clamped`` runs the same variants over McGuire's own NeighborMax (half-velocities
   clamped to k, from a blur with packed inputs).
3. ``dispatch``: McGuire's packed reconstruct pass dispatched by blurlab (the recorded pass
   replayed), the same shader source compiled and dispatched by moderngl on the same textures,
   and part 2's model over blurlab's NeighborMax: whether blurlab's binding and dispatch, or
   the shader, makes the difference.
4. ``coverage``: gather_coverage's gather pass dispatched by blurlab, and through moderngl with
   its uniforms made constants one group at a time.
5. ``barriers``: a pass over one texel and one over the frame, back to back, with the memory
   barrier every blurlab pass ends with (all bits), with only the bits a following pass's
   texel fetches and image accesses need, and with none.
6. ``coverage_costs``: gather_coverage's gather through moderngl as it is and with one kind of
   work taken out of every tap at a time (a fetch, the sanitising of an input, the trail test;
   COVERAGE_COSTS), with everything but X's own reads and write taken out, with 4 and 6 taps a
   half-shutter and with its reach cut to 40 px: which work holds the pass. Then with its
   inputs read as half floats (HALF_INPUTS: motion, colour, colour with the depth in alpha), as
   an engine's G-buffer would store them. The edits give other images; they time, they do not
   filter.

Medians over --runs: on a GPU by GL timer queries (50 dispatches back to back behind busy work,
and one dispatch under its own timer); on llvmpipe by glFinish and a wall clock, which ranks
nothing.

    python benchmarks/filter_time.py [--device gpu] [--size 1920x1080]
        [--parts passes,fetch,fetch_clamped,dispatch,coverage,barriers,coverage_costs]
        [--scene teapot_pass] [--runs 20] [--json f]
"""

from __future__ import annotations

import argparse
import re
import statistics
import time
from pathlib import Path

import numpy as np

import blurlab as bl
from blurlab._paths import shader_dir
from blurlab.methods import eevee, plans
from blurlab.methods.core import frame_textures, method, resolve_params
from blurlab.methods.tile_filter import variant_defines

from common import back_to_back_ms, describe, open_context, save, spin_up

PARTS = ("passes", "fetch", "fetch_clamped", "dispatch", "coverage", "barriers", "coverage_costs")
K = 20  # McGuire 2012's tile side at the issue's configuration
SAMPLES = 15

# One pixel's 16 bytes (packed_words): colour as four halves, motion as two, depth as one.
UNPACK = """
void unpack(uvec4 t, out vec4 c, out vec2 m, out float z) {
    c = vec4(unpackHalf2x16(t.x), unpackHalf2x16(t.y));
    m = unpackHalf2x16(t.z);
    z = unpackHalf2x16(t.w).x;
}"""
FETCH = {
    "two_textures": """
layout(binding = 0) uniform sampler2D color;
layout(binding = 1) uniform sampler2D motion_depth;
void texel_at(ivec2 p, out vec4 c, out vec2 m, out float z) {
    c = texelFetch(color, p, 0);
    vec4 t = texelFetch(motion_depth, p, 0);
    m = t.xy;
    z = t.z;
}""",
    "one_texture": UNPACK
    + """
layout(binding = 0) uniform usampler2D pixels;
void texel_at(ivec2 p, out vec4 c, out vec2 m, out float z) {
    unpack(texelFetch(pixels, p, 0), c, m, z);
}""",
    "buffer_rows": UNPACK
    + """
layout(std430, binding = 0) readonly buffer Pixels { uvec4 pixels[]; };
void texel_at(ivec2 p, out vec4 c, out vec2 m, out float z) {
    unpack(pixels[p.y * size.x + p.x], c, m, z);
}""",
    "buffer_blocks": UNPACK
    + """
layout(std430, binding = 0) readonly buffer Pixels { uvec4 pixels[]; };
void texel_at(ivec2 p, out vec4 c, out vec2 m, out float z) {
    int blocks_x = (size.x + 7) / 8;
    int i = ((p.y >> 3) * blocks_x + (p.x >> 3)) * 64 + (p.y & 7) * 8 + (p.x & 7);
    unpack(pixels[i], c, m, z);
}""",
}

GATHER = """
float half_length(vec2 v) { return max(length(v), 0.5); }
vec2 half_velocity(vec2 motion) {
    vec2 q = motion * 0.5;
    float n = length(q);
    return n == 0.0 ? vec2(0.0) : q * (clamp(n, 0.5, float(K)) / max(n, 1e-6));
}
float cone(float dist, vec2 v) { return clamp(1.0 - dist / half_length(v), 0.0, 1.0); }
float cylinder(float dist, vec2 v) {
    float l = half_length(v);
    return 1.0 - smoothstep(0.95 * l, 1.05 * l, dist);
}
float closer(float za, float zb) {
    float d = za == zb ? 0.0 : zb - za;
    return clamp(1.0 - d, 0.0, 1.0);
}
#ifdef PCG_JITTER  // the filters' own hash, common/random.glsl's rand
uint pcg(uint v) {
    uint s = v * 747796405u + 2891336453u;
    uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}
float jitter(ivec2 p) {
    return float(pcg(uint(p.x) ^ pcg(uint(p.y) ^ pcg(0u))) >> 8u) * (1.0 / 16777216.0) - 0.5;
}
#else
float jitter(ivec2 p) {
    uint h = uint(p.x) * 1973u + uint(p.y) * 9277u + 26699u;
    h = (h ^ (h >> 16)) * 0x7feb352du;
    h = (h ^ (h >> 15)) * 0x846ca68bu;
    return float((h ^ (h >> 16)) & 0xffffu) / 65536.0 - 0.5;
}
#endif
#ifdef RUNTIME_SAMPLES  // the count a uniform, as the filters take it: the loop cannot unroll
uniform int samples;
#else
const int samples = SAMPLES;
#endif

vec4 gather_at(ivec2 x) {
    vec4 cx; vec2 mx; float zx;
    texel_at(x, cx, mx, zx);
#ifdef CENTRE_ONLY
    return cx + vec4(mx, zx, 0.0) * 1e-30;
#else
    vec2 vn = texelFetch(neighbor_max, x / K, 0).xy;
    if (length(vn) <= 0.5 + 0.01) return cx;  // McGuire's test (common/filter_options.glsl)
    vec2 vx = half_velocity(mx);
    float weight = 1.0 / half_length(vx);
    vec4 sum = cx * weight;
#ifdef NO_JITTER
    float j = 0.0;
#else
    float j = jitter(x);
#endif
    vec2 centre = vec2(x) + 0.5;
    for (int i = 0; i < samples; ++i) {
        if (i == samples / 2) continue;
        float t = -1.0 + 2.0 * (float(i) + j + 1.0) / float(samples + 1);
        ivec2 y = clamp(ivec2(floor(centre + vn * t)), ivec2(0), size - 1);
        vec4 cy; vec2 my; float zy;
        texel_at(y, cy, my, zy);
        vec2 vy = half_velocity(my);
        float dist = length(vec2(y - x));
        float a = closer(zx, zy) * cone(dist, vy) + closer(zy, zx) * cone(dist, vx)
                + cylinder(dist, vy) * cylinder(dist, vx) * 2.0;
        weight += a;
        sum += a * cy;
    }
    return sum / weight;
#endif
}

void main() {
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(x, size))) return;
    imageStore(result, x, gather_at(x));
}
"""


FILTER_RUNS = [  # label, method, parameters
    ("reconstruct_mcguire2012", "reconstruct_mcguire2012", {"k": K, "samples": SAMPLES}),
    (
        "reconstruct_mcguire2012 packed",
        "reconstruct_mcguire2012",
        {"k": K, "samples": SAMPLES, "packed_inputs": True},
    ),
    ("reconstruct_guertin2014", "reconstruct_guertin2014", {}),
    ("reconstruct_guertin2014 packed", "reconstruct_guertin2014", {"packed_inputs": True}),
    ("gather_coverage", "gather_coverage", {}),
    ("gather_coverage, film_filter=0.5", "gather_coverage", {"film_filter": 0.5}),
    ("gather_coverage, gather dilation", "gather_coverage", {}),
    ("gather_coverage, scatter dilation", "gather_coverage", {}),
    ("gather_coverage, keys resolved in the gather", "gather_coverage", {}),
]
# Runs taken with a named dilation (methods.eevee.DILATION_VARIANTS), whatever the default.
DILATION_OF = {
    "gather_coverage, gather dilation": "gather",
    "gather_coverage, scatter dilation": "scatter",
    "gather_coverage, keys resolved in the gather": "scatter_in_gather",
}


def recorded_passes(ctx, frame, name: str, params: dict) -> list:
    """The passes of one run of method `name`, as blurlab.methods.plans records them."""
    m = method(name)
    values = resolve_params(m, frame, params)
    recorder = plans.Recorder()
    with plans.recording(recorder):
        m.run(ctx, frame, frame_textures(ctx, frame), values, "compute")
    return list(zip(recorder.timing_names, recorder.runs, strict=True))


def replay(passes: list) -> None:
    for _, run in passes:
        run.shader.run(run.inputs, run.outputs, run.uniforms, run.backend, run.group_per_texel)


def film_from_half(ctx, run, runs: int) -> dict:
    """The recorded film pass reading the gather's image as RGBA16F instead of RGBA32F (the
    read half of handing the film a half-float image): ms back to back, and the largest
    difference that rounding makes."""
    ((source_name, source),) = run.inputs.items()
    half = ctx.upload(source.download().astype(np.float16))
    inputs = {source_name: half}
    output = ctx.pooled(run.outputs["result"].shape)

    def film():
        run.shader.run(inputs, {"result": output}, run.uniforms, run.backend, run.group_per_texel)

    film()
    difference = np.abs(output.download() - run.outputs["result"].download())
    ms = statistics.median(back_to_back_ms(ctx, film) for _ in range(runs))
    ctx.recycle(output, half)
    return {"back_to_back_ms": ms, "largest_difference": float(difference.max())}


def one_texel_dispatch_ms(ctx, runs: int) -> float:
    """A pass over one texel (accumulate.comp), back to back: what any dispatch costs, with the
    memory barrier every blurlab pass issues after it."""
    source, total = ctx.empty((1, 1, 4)), ctx.empty((1, 1, 4))
    shader = ctx.shader_pass("passes/accumulate.comp")

    def dispatch():
        shader.run({"color": source}, {"sum": total}, {"weight": 0.5})

    ms = statistics.median(back_to_back_ms(ctx, dispatch) for _ in range(runs))
    ctx.recycle(source, total)
    return ms


def filter_passes(ctx, frame, runs: int) -> dict:
    """Part 1 of the module's list: ms per pass alone and per prefix of the passes, back to back."""
    runs = min(runs, 5)  # each back_to_back_ms is already a mean over 50 calls
    record = {"one_texel_dispatch_ms": one_texel_dispatch_ms(ctx, runs)}
    print(f"one-texel dispatch: {record['one_texel_dispatch_ms']:.4f} ms back to back", flush=True)
    for label, name, params in FILTER_RUNS:
        with eevee.DILATION_LAYOUT.use(DILATION_OF.get(label, eevee.DILATION_LAYOUT.default)):
            passes = recorded_passes(ctx, frame, name, params)
        alone = {
            step: statistics.median(
                back_to_back_ms(ctx, lambda p=[(step, run)]: replay(p)) for _ in range(runs)
            )
            for step, run in passes
        }
        prefixes = {
            "+".join(step for step, _ in passes[:n]): statistics.median(
                back_to_back_ms(ctx, lambda p=passes[:n]: replay(p)) for _ in range(runs)
            )
            for n in range(1, len(passes) + 1)
        }
        whole = prefixes["+".join(step for step, _ in passes)]
        record[label] = {
            "alone_ms": alone,
            "prefixes_ms": prefixes,
            "sum_alone_ms": sum(alone.values()),
            "all_passes_ms": whole,
            "boundaries_ms": whole - sum(alone.values()),
        }
        cells = ", ".join(f"{step} {ms:.4f}" for step, ms in alone.items())
        print(f"{label}: alone {cells}; all {whole:.4f} ms back to back", flush=True)
        if "film_filter" in params:
            record[label]["film_from_half"] = film_from_half(ctx, passes[-1][1], runs)
            print(f"  film reading RGBA16F: {record[label]['film_from_half']}", flush=True)
    return record


def shader_source(fetch: str, output_format: str, centre_only: bool, extra: tuple = ()) -> str:
    head = [
        "#version 450",
        "layout(local_size_x = 16, local_size_y = 16) in;",
        f"const int K = {K};",
        f"const int SAMPLES = {SAMPLES};",
        "uniform ivec2 size;",
        "layout(binding = 2) uniform sampler2D neighbor_max;",
        f"layout(binding = 0, {output_format}) uniform writeonly image2D result;",
    ]
    if centre_only:
        head.append("#define CENTRE_ONLY")
    head.extend(f"#define {name}" for name in extra)
    return "\n".join(head) + FETCH[fetch] + GATHER


def neighbor_max(motion: np.ndarray) -> np.ndarray:
    """McGuire's TileMax then 3 x 3 NeighborMax of the half-vectors' directions, in NumPy: the
    largest motion of each tile, then of its neighbours (the gather's direction)."""
    height, width = motion.shape[:2]
    rows, cols = -(-height // K), -(-width // K)
    padded = np.zeros((rows * K, cols * K, 2), np.float32)
    padded[:height, :width] = motion
    blocks = padded.reshape(rows, K, cols, K, 2).transpose(0, 2, 1, 3, 4).reshape(rows, cols, -1, 2)
    pick = np.linalg.norm(blocks, axis=-1).argmax(axis=-1)
    tiles = np.take_along_axis(blocks, pick[..., None, None], axis=2)[:, :, 0] * 0.5
    best = tiles.copy()
    bordered = np.pad(tiles, ((1, 1), (1, 1), (0, 0)))
    for dy in range(3):
        for dx in range(3):
            other = bordered[dy : dy + rows, dx : dx + cols]
            longer = np.linalg.norm(other, axis=-1) > np.linalg.norm(best, axis=-1)
            best[longer] = other[longer]
    return best.astype(np.float32)


def packed_words(color: np.ndarray, motion: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """(H, W, 4) uint32: colour as four halves, motion as two, depth as one (and a zero half),
    the low half of each word first, as unpackHalf2x16 reads it."""
    halves = np.concatenate(
        [color, motion, depth[..., None], np.zeros_like(depth)[..., None]], axis=-1
    ).astype(np.float16)
    return halves.view(np.uint32)


def blocks_of_8(words: np.ndarray) -> np.ndarray:
    """The words in 8 x 8 blocks, row by row of blocks, pixels row by row in a block."""
    height, width = words.shape[:2]
    rows, cols = -(-height // 8), -(-width // 8)
    padded = np.zeros((rows * 8, cols * 8, 4), np.uint32)
    padded[:height, :width] = words
    return padded.reshape(rows, 8, cols, 8, 4).transpose(0, 2, 1, 3, 4).copy()


# name: (how the taps read, output format, centre only, extra defines)
FETCH_VARIANTS = {
    "two_textures": ("two_textures", "rgba32f", False, ()),
    "one_texture": ("one_texture", "rgba32f", False, ()),
    "buffer_rows": ("buffer_rows", "rgba32f", False, ()),
    "buffer_blocks": ("buffer_blocks", "rgba32f", False, ()),
    "two_textures_half_out": ("two_textures", "rgba16f", False, ()),
    "two_textures_runtime_samples": ("two_textures", "rgba32f", False, ("RUNTIME_SAMPLES",)),
    "two_textures_pcg": ("two_textures", "rgba32f", False, ("PCG_JITTER",)),
    "two_textures_runtime_samples_pcg": (
        "two_textures",
        "rgba32f",
        False,
        ("RUNTIME_SAMPLES", "PCG_JITTER"),
    ),
    "two_textures_no_jitter": ("two_textures", "rgba32f", False, ("NO_JITTER",)),
    "buffer_rows_no_jitter": ("buffer_rows", "rgba32f", False, ("NO_JITTER",)),
    "centre_only": ("two_textures", "rgba32f", True, ()),
    "centre_only_one_texture": ("one_texture", "rgba32f", True, ()),
    "centre_only_buffer_rows": ("buffer_rows", "rgba32f", True, ()),
}
SAMPLER_UNITS = {"color": 0, "motion_depth": 1, "pixels": 0, "neighbor_max": 2}


def fetch_sources(mgl, frame, tiles=None) -> tuple[dict, dict, np.ndarray]:
    """teapot_pass's inputs rounded to halves as each fetch path reads them: moderngl textures
    by sampler name, storage buffers by variant, and the NeighborMax grid (`tiles`, or
    neighbor_max's)."""
    depth = np.where(np.isfinite(frame.depth), np.clip(frame.depth, 6.1035156e-5, 65504), np.inf)
    color = np.clip(frame.color, -65504, 65504).astype(np.float16)
    motion = np.clip(frame.motion, -65504, 65504).astype(np.float16)
    words = packed_words(color, motion, depth.astype(np.float32))
    motion_depth = np.concatenate(
        [motion, depth.astype(np.float16)[..., None], np.zeros_like(motion[..., :1])], axis=-1
    )
    tiles = neighbor_max(motion.astype(np.float32)) if tiles is None else tiles

    def texture(array, dtype):
        height, width, channels = array.shape
        return mgl.texture((width, height), channels, array.tobytes(), dtype=dtype)

    textures = {
        "color": texture(color, "f2"),
        "motion_depth": texture(motion_depth, "f2"),
        "pixels": texture(words, "u4"),
        "neighbor_max": texture(tiles, "f4"),
    }
    buffers = {
        "buffer_rows": mgl.buffer(words.tobytes()),
        "buffer_blocks": mgl.buffer(blocks_of_8(words).tobytes()),
    }
    return textures, buffers, tiles


def dispatch_ms(ctx, mgl, dispatch, runs: int) -> tuple[float, float]:
    """Medians of (one dispatch under its own timer, a dispatch of 50 issued back to back behind
    busy work); on llvmpipe both are glFinish + wall clock of one dispatch."""
    spin_up(dispatch)
    alone, in_a_row = [], []
    if ctx.info()["timer"] != "gl_time_elapsed":  # llvmpipe's timer queries read near zero
        for _ in range(runs):
            mgl.finish()
            start = time.perf_counter()
            dispatch()
            mgl.finish()
            alone.append((time.perf_counter() - start) * 1e3)
        return statistics.median(alone), statistics.median(alone)
    busy_target = mgl.texture((2048, 2048), 4, dtype="f4")
    busy = mgl.compute_shader(
        "#version 450\nlayout(local_size_x = 16, local_size_y = 16) in;\n"
        "layout(binding = 0, rgba32f) uniform image2D busy;\n"
        "void main() { ivec2 p = ivec2(gl_GlobalInvocationID.xy);"
        " imageStore(busy, p, imageLoad(busy, p) * 0.5 + 1.0); }"
    )
    for _ in range(runs):
        query = mgl.query(time=True)
        with query:
            dispatch()
        alone.append(query.elapsed / 1e6)
        busy_target.bind_to_image(0, read=True, write=True)
        for _ in range(40):  # about 20 ms on the H100: the GPU is busy while the CPU issues
            busy.run(128, 128)
        query = mgl.query(time=True)
        with query:
            for _ in range(50):
                dispatch()
        in_a_row.append(query.elapsed / 1e6 / 50)
    busy_target.release()
    busy.release()
    return statistics.median(alone), statistics.median(in_a_row)


def fetch_paths(ctx, frame, runs: int, tiles=None) -> dict:
    """Part 2 of the module's list (`tiles`: the NeighborMax grid, default neighbor_max's)."""
    mgl = ctx.moderngl()
    height, width = frame.color.shape[:2]
    textures, buffers, tiles = fetch_sources(mgl, frame, tiles)
    outputs = {"rgba32f": mgl.texture((width, height), 4, dtype="f4")}
    outputs["rgba16f"] = mgl.texture((width, height), 4, dtype="f2")
    groups = (-(-width // 16), -(-height // 16))
    record: dict = {"k": K, "samples": SAMPLES, "variants": {}}
    images = {}
    for name, (fetch, output_format, centre_only, defines) in FETCH_VARIANTS.items():
        program = mgl.compute_shader(shader_source(fetch, output_format, centre_only, defines))
        program["size"] = (width, height)
        if "RUNTIME_SAMPLES" in defines:
            program["samples"] = SAMPLES
        for sampler, unit in SAMPLER_UNITS.items():
            if sampler in program:
                program[sampler] = unit
                textures[sampler].use(unit)
        if fetch in buffers:
            buffers[fetch].bind_to_storage_buffer(0)
        output = outputs[output_format]

        def dispatch(program=program, output=output):
            output.bind_to_image(0, read=False, write=True)
            program.run(*groups)
            mgl.memory_barrier()

        alone, in_a_row = dispatch_ms(ctx, mgl, dispatch, runs)
        dtype = np.float32 if output_format == "rgba32f" else np.float16
        image = np.frombuffer(output.read(), dtype).reshape(height, width, 4)
        images[name] = image.astype(np.float32)
        record["variants"][name] = {"one_dispatch_ms": alone, "back_to_back_ms": in_a_row}
        print(f"{name:34s} one dispatch {alone:.4f} ms, back to back {in_a_row:.4f} ms", flush=True)
        program.release()
    for name, image in images.items():
        if name.startswith("centre_only"):
            continue
        # The PCG and unjittered variants jitter otherwise: each is compared with its kin.
        if "no_jitter" in name:
            base = images["two_textures_no_jitter"]
        else:
            base = images["two_textures_pcg" if "pcg" in name else "two_textures"]
        difference = np.abs(image - base)
        record["variants"][name]["largest_difference"] = float(difference.max())
        record["variants"][name]["share_within_1e-3"] = float((difference <= 1e-3).mean())
    record["tiles_with_taps"] = float((np.linalg.norm(tiles, axis=-1) > 0.5 + 0.01).mean())
    return record


def expanded_source(path: str, defines: dict) -> str:
    """A blurlab shader with its includes expanded once each and `defines` after #version, as
    the C++ core builds it (src/gl/program.cpp), for moderngl to compile."""
    root = shader_dir()
    seen: set = set()

    def expand(file: Path) -> list[str]:
        lines = []
        for line in file.read_text().splitlines():
            include = re.fullmatch(r'\s*#\s*include\s+"([^"]+)"\s*', line)
            if include is None:
                lines.append(line)
                continue
            target = file.parent / include[1]
            target = target if target.is_file() else root / include[1]
            if target.resolve() not in seen:
                seen.add(target.resolve())
                lines += expand(target)
        return lines

    lines = expand(root / path)
    head = [f"#define {name} {value}" for name, value in defines.items()]
    return "\n".join([lines[0], *head, *lines[1:]])


# Part 3's variants of the real source. Since the fifth stop the options are #defines
# (tile_filter.variant_defines); "the options as uniforms" puts back how they were before, which
# the H100 measured at 15 % of the pass. The rest make one uniform at a time a constant (its
# value this run's) or take half_velocity's overflow branch out.
OPTIONS_AS_UNIFORMS = "the options as uniforms (before)"
CONSTANTS = {  # label: uniforms made constants
    OPTIONS_AS_UNIFORMS: (),
    "k constant": ("k",),
    "S constant": ("samples",),
    "soft_z constant": ("soft_z",),
    "exposure constant": ("exposure",),
    "early_exit constant": ("early_exit",),
    "no overflow branch": (),
    "everything constant, no overflow branch": ("k", "samples", "soft_z", "exposure", "early_exit"),
}


def with_constants(source: str, uniforms: dict, names, int_names, label: str) -> str:
    """`source` with each uniform of `names` declared a constant at its value in `uniforms`
    (`int_names` are ints, the rest floats)."""
    for name in names:
        kind = "int" if name in int_names else "float"
        value = uniforms[name]
        literal = str(int(value)) if kind == "int" else repr(float(value))
        uniform = f"uniform {kind} {name};"
        assert uniform in source, f"{label}: the shader declares no {uniform}"
        source = source.replace(uniform, f"const {kind} {name} = {literal};")
    return source


def moderngl_dispatch(mgl, current, inputs: dict, units: dict, output, groups):
    """A dispatch, through moderngl, of the program current() returns, over `inputs` (moderngl
    textures by sampler name) bound at `units`, into image `output`, then a barrier."""

    def dispatch():
        shader = current()
        for name, unit in units.items():
            inputs[name].use(unit)
            if name in shader:  # an edit of the source may leave a sampler unread
                shader[name] = unit
        output.bind_to_image(0, read=False, write=True)
        shader.run(*groups)
        mgl.memory_barrier()

    return dispatch


def wrapped_inputs(mgl, run) -> dict:
    """The recorded pass's input textures, wrapped for moderngl (not owned: never released)."""
    return {
        name: mgl.external_texture(
            texture.glo,
            (texture.width, texture.height),
            texture.channels,
            0,
            "u4" if texture.dtype == np.uint32 else "f4",
        )
        for name, texture in run.inputs.items()
    }


def blurlab_or_moderngl(ctx, frame, runs: int) -> dict:
    """Part 3 of the module's list: McGuire's packed reconstruct pass three ways on the same
    textures: dispatched by blurlab (the recorded pass replayed), the same shader source
    compiled and dispatched by moderngl, and part 2's model gather (two_textures) over
    blurlab's own NeighborMax. Where the first two differ, the difference lies in how blurlab
    binds and dispatches; where the last two do, in the shader."""
    mgl = ctx.moderngl()
    height, width = frame.color.shape[:2]
    passes = recorded_passes(ctx, frame, *FILTER_RUNS[1][1:])
    _, run = passes[-1]
    replay(passes)
    blurlab_output = run.outputs["result"]
    groups = (-(-width // 16), -(-height // 16))
    wrapped = wrapped_inputs(mgl, run)
    output = mgl.texture((width, height), 4, dtype="f4")
    record: dict = {}
    images: dict = {}

    def timed(name, dispatch, read):
        one, in_a_row = dispatch_ms(ctx, mgl, dispatch, runs)
        mgl.finish()
        images[name] = read()
        record[name] = {"one_dispatch_ms": one, "back_to_back_ms": in_a_row}
        print(f"{name:34s} one dispatch {one:.4f} ms, back to back {in_a_row:.4f} ms", flush=True)

    def read_output():
        return np.frombuffer(output.read(), np.float32).reshape(height, width, 4)

    timed("blurlab", lambda: replay([passes[-1]]), blurlab_output.download)
    filter_name, params = FILTER_RUNS[1][1:]
    defines = variant_defines(resolve_params(method(filter_name), frame, params))
    source = expanded_source(f"passes/{filter_name}.glsl", {"STAGE_COMPUTE": 1, **defines})
    program = mgl.compute_shader(source)
    for name, value in run.uniforms.items():
        program[name] = value

    real_units = {"color": 0, "motion_depth": 1, "neighbor_max": 3}  # the pass's bindings
    dispatch_real = moderngl_dispatch(mgl, lambda: program, wrapped, real_units, output, groups)
    timed("same shader, moderngl", dispatch_real, read_output)
    for label, names in CONSTANTS.items():
        program.release()
        variant = source
        if label == OPTIONS_AS_UNIFORMS:
            for option in ("jitter_tiles", "adaptive_samples"):
                declared = f"const bool {option} = {option.upper()} != 0;"
                assert declared in variant, f"{label}: the shader declares no {declared}"
                variant = variant.replace(declared, f"uniform bool {option};")
        variant = with_constants(variant, run.uniforms, names, ("k", "samples"), label)
        if "no overflow branch" in label:
            variant = variant.replace("if (isinf(n)) {", "if (false) {")
        program = mgl.compute_shader(variant)
        for name, value in run.uniforms.items():
            if name in program:
                program[name] = value
        for option in ("jitter_tiles", "adaptive_samples"):
            if option in program:  # the options as uniforms, at this run's values
                program[option] = defines[option.upper()]
        timed(f"same shader, {label}", dispatch_real, read_output)
    record["constants_same_bits"] = {
        label: bool(np.array_equal(images["blurlab"], images[f"same shader, {label}"]))
        for label in CONSTANTS
    }
    model = mgl.compute_shader(shader_source("two_textures", "rgba32f", False))
    model["size"] = (width, height)
    model_units = {"color": 0, "motion_depth": 1, "neighbor_max": 2}  # shader_source's
    dispatch_model = moderngl_dispatch(mgl, lambda: model, wrapped, model_units, output, groups)
    timed("model gather, blurlab's NeighborMax", dispatch_model, read_output)
    same = np.array_equal(images["blurlab"], images["same shader, moderngl"])
    record["same_shader_same_bits"] = bool(same)
    program.release()
    model.release()
    output.release()
    return record


GATHER_CONSTANTS = {  # label: gather_coverage's gather uniforms made constants (part 4)
    "samples constant": ("samples",),
    "tile_size constant": ("tile_size",),
    "everything constant": ("samples", "tile_size", "reach_limit", "soft_z", "exposure"),
}


def coverage_gather_constants(ctx, frame, runs: int) -> dict:
    """Part 4: gather_coverage's gather pass dispatched by blurlab and, through moderngl, with
    its uniforms made constants: whether a sample count known when the pass is built (the taps'
    loops unroll) would pay, as the options' #defines did for the tile filters."""
    mgl = ctx.moderngl()
    height, width = frame.color.shape[:2]
    # The gather as it reads a resolved dilated grid (the scatter dilation): the source below is
    # compiled without GATHER_READS_KEYS.
    with eevee.DILATION_LAYOUT.use("scatter"):
        passes = recorded_passes(ctx, frame, "gather_coverage", {})
    step, run = passes[-1]
    assert step == "gather", step
    replay(passes)
    groups = (-(-width // 16), -(-height // 16))
    wrapped = wrapped_inputs(mgl, run)
    units = {"color": 0, "depth": 1, "motion_sides": 2, "dilated": 3}
    output = mgl.texture((width, height), 4, dtype="f4")
    source = expanded_source("passes/coverage_gather.glsl", {"STAGE_COMPUTE": 1})
    record: dict = {}
    expected = run.outputs["result"].download()
    one, in_a_row = dispatch_ms(ctx, mgl, lambda: replay([passes[-1]]), runs)
    record["blurlab"] = {"one_dispatch_ms": one, "back_to_back_ms": in_a_row}
    print(f"{'gather, blurlab':34s} one dispatch {one:.4f} ms, back to back {in_a_row:.4f} ms")
    bound = (wrapped, units, output, groups)
    for label, names in {"same source": (), **GATHER_CONSTANTS}.items():
        variant = with_constants(source, run.uniforms, names, ("samples", "tile_size"), label)
        record[label] = gather_variant_row(ctx, mgl, variant, run.uniforms, bound, expected, runs)
        row = record[label]
        print(
            f"{'gather, ' + label:34s} one dispatch {row['one_dispatch_ms']:.4f} ms,"
            f" back to back {row['back_to_back_ms']:.4f} ms"
        )
    output.release()
    return record


def gather_variant_row(ctx, mgl, variant: str, uniforms: dict, bound, expected, runs) -> dict:
    """Parts 4 and 6: a variant of the gather's source compiled by moderngl, its `uniforms` set
    (those it still declares), dispatched over bound = (inputs, units, output image, groups)
    and timed; whether its image has the bits of `expected`."""
    inputs, units, output, groups = bound
    program = mgl.compute_shader(variant)
    for name, value in uniforms.items():
        if name in program:
            program[name] = value
    dispatch = moderngl_dispatch(mgl, lambda: program, inputs, units, output, groups)
    one, in_a_row = dispatch_ms(ctx, mgl, dispatch, runs)
    mgl.finish()
    image = np.frombuffer(output.read(), np.float32).reshape(expected.shape)
    program.release()
    return {
        "one_dispatch_ms": one,
        "back_to_back_ms": in_a_row,
        "same_bits": bool(np.array_equal(image, expected)),
        "largest_change": float(np.max(np.abs(image - expected))),
    }


# Part 6: edits of the gather's source that each take one kind of work out of every tap, to
# tell which kind holds the pass. None gives gather_coverage's image (timing only): each takes
# out what it names and leaves the rest of a tap's work as it is.
TAP_LINE = "ivec2 y = clamp(ivec2(floor(center + along * t + bent)), ivec2(0), size - 1);"
COVERAGE_COSTS = {  # label: (text of coverage_gather.glsl, what replaces it), ...
    "taps read next to X (texture caches always hit)": (
        (TAP_LINE, TAP_LINE + " y = clamp(x + ivec2(i % 2, side), ivec2(0), size - 1);"),
    ),
    "no depth fetch at the taps (read from colour alpha)": (
        (
            "float zy = sanitize_depth(texelFetch(depth, y, 0).x);",
            "float zy = sanitize_depth(texelFetch(color, y, 0).w);",
        ),
    ),
    "no colour fetch at the taps": (
        ("vec4 cy = sanitize_color(texelFetch(color, y, 0));", "vec4 cy = vec4(zy);"),
    ),
    "no motion fetch at the taps (X's own)": (
        ("vec4 halves = halves_at(y);", "vec4 halves = x_halves;"),
    ),
    "no trail test (every tap reaches)": (
        (
            "float reaches = trail_reaches(vec2(y - x), vy, speed, 0.5 * (halves.zw - halves.xy));",
            "float reaches = 1.0;",
        ),
    ),
    "taps' colour not sanitised": (
        (
            "vec4 cy = sanitize_color(texelFetch(color, y, 0));",
            "vec4 cy = texelFetch(color, y, 0);",
        ),
    ),
    "taps' depth not sanitised": (
        (
            "float zy = sanitize_depth(texelFetch(depth, y, 0).x);",
            "float zy = texelFetch(depth, y, 0).x;",
        ),
    ),
    "motion not sanitised (X's and the taps')": (
        ("vec2 v = scaled_motion(m, exposure);", "vec2 v = m * exposure;"),
    ),
    "early exit everywhere (X, its tile, the write)": (
        ("if (max(length(lines[0]), length(lines[1])) < EARLY_EXIT) return cx;", "return cx;"),
    ),
}


# Part 6 also times rewrites of the gather that give its very image (the record's same_bits
# says whether they do) with other instructions: candidates for the shader. On the H100 none of
# these was faster on all three scenes tried (docs/benchmarks.md, "What a tap costs").
TAP_CENTRE = "    vec2 center = vec2(x) + 0.5;\n"
FLOAT_TAP = (  # the tap's texel found in floats and read at its centre: no int/float conversion
    (
        TAP_CENTRE,
        TAP_CENTRE + "    vec2 xf = vec2(x), last = vec2(size - 1), texel = 1.0 / vec2(size);\n",
    ),
    (
        TAP_LINE,
        "vec2 yf = clamp(floor(center + along * t + bent), vec2(0.0), last);"
        " vec2 uv = (yf + 0.5) * texel;",
    ),
    (
        "vec4 halves = halves_at(y);",
        "vec4 m = textureLod(motion_sides, uv, 0.0);"
        " vec4 halves = vec4(clamped_half(m.xy), clamped_half(m.zw));",
    ),
    ("texelFetch(depth, y, 0).x", "textureLod(depth, uv, 0.0).x"),
    (
        "vec4 cy = sanitize_color(texelFetch(color, y, 0));",
        "vec4 cy = sanitize_color(textureLod(color, uv, 0.0));",
    ),
    ("trail_reaches(vec2(y - x),", "trail_reaches(yf - xf,"),
)
FLOAT_PAIR = (  # the pair index counted in a float: no conversion of i >> 1
    (
        "        for (int i = 0; i < samples; ++i) {\n",
        "        float pair = 0.0;\n        for (int i = 0; i < samples; ++i) {\n",
    ),
    ("float t = (float(i >> 1) +", "float t = (pair +"),
    (
        "            // X's own family follows",
        "            pair += family_1 ? 1.0 : 0.0;\n            // X's own family follows",
    ),
)
COVERAGE_CANDIDATES = {
    "candidate: tap texel in floats, read at its centre": FLOAT_TAP,
    "candidate: pair index in a float": FLOAT_PAIR,
    "candidate: both": FLOAT_TAP + FLOAT_PAIR,
    "candidate: colour read only where weighted (GATHER_SKIP_UNWEIGHTED)": (
        (
            "#define STAGE_COMPUTE 1\n",
            "#define STAGE_COMPUTE 1\n#define GATHER_SKIP_UNWEIGHTED 1\n",
        ),
    ),
}


def coverage_costs(ctx, frame, runs: int) -> dict:
    """Part 6: gather_coverage's gather (as the default dilation feeds it, keys resolved in the
    gather) through moderngl as it is, with each edit of COVERAGE_COSTS and each rewrite of
    COVERAGE_CANDIDATES; with 4 and 6 taps a half-shutter, to price a tap; and with its reach
    cut to 40 px."""
    mgl = ctx.moderngl()
    height, width = frame.color.shape[:2]
    passes = recorded_passes(ctx, frame, "gather_coverage", {})
    step, run = passes[-1]
    assert step == "gather", step
    replay(passes)
    groups = (-(-width // 16), -(-height // 16))
    units = {"color": 0, "depth": 1, "motion_sides": 2, "tiles": 3, "reach_keys": 4}
    wrapped = wrapped_inputs(mgl, run)
    output = mgl.texture((width, height), 4, dtype="f4")
    source = expanded_source(
        "passes/coverage_gather.glsl", {"STAGE_COMPUTE": 1, "GATHER_READS_KEYS": 1}
    )
    expected = run.outputs["result"].download()
    record: dict = {}
    # label: (edits of the source, uniforms changed, inputs swapped)
    variants = {"same source": ((), {}, {})}
    variants |= {
        label: (edits, {}, {}) for label, edits in (COVERAGE_COSTS | COVERAGE_CANDIDATES).items()
    }
    variants |= {f"{n} taps a half-shutter": ((), {"samples": n}, {}) for n in (4, 6)}
    # Taps within 40 px, guertin2014's reach at 1080p, instead of 324: what the texture caches
    # lose to the long reach (the keys' tiles still reach as far).
    variants["reach limited to 40 px"] = ((), {"reach_limit": 40.0}, {})
    halves = half_inputs(mgl, run)
    for label, (edits, inputs) in HALF_INPUTS.items():
        variants[label] = (edits, {}, {name: halves[key] for name, key in inputs.items()})
    for label, (edits, uniforms, swapped) in variants.items():
        variant = source
        for old, new in edits:
            assert old in variant, f"{label}: the gather has no {old!r}"
            variant = variant.replace(old, new)
        bound = (wrapped | swapped, units, output, groups)
        row = gather_variant_row(ctx, mgl, variant, run.uniforms | uniforms, bound, expected, runs)
        record[label] = row
        print(
            f"{label:52s} one dispatch {row['one_dispatch_ms']:.4f} ms,"
            f" back to back {row['back_to_back_ms']:.4f} ms"
            + ("" if row["same_bits"] else f", largest change {row['largest_change']:.2e}"),
            flush=True,
        )
    for texture in halves.values():
        texture.release()
    output.release()
    return record


# Part 6 also reads the gather's inputs as half floats (RGBA16F), as an engine's G-buffer would
# write them (EEVEE keeps its two-sided motion in rgba16f): what fewer bytes a tap would save.
# Timing only; the record's largest_change says how far the image moved. label: (edits of the
# source, {sampler: texture of half_inputs}).
HALF_INPUTS = {
    "half inputs: motion RGBA16F": ((), {"motion_sides": "motion"}),
    "half inputs: colour RGBA16F": ((), {"color": "color"}),
    "half inputs: motion and colour RGBA16F": ((), {"motion_sides": "motion", "color": "color"}),
    "half inputs: motion RGBA16F, colour + depth RGBA16F": (
        COVERAGE_COSTS["no depth fetch at the taps (read from colour alpha)"],
        {"motion_sides": "motion", "color": "color_depth"},
    ),
}


def half_inputs(mgl, run) -> dict:
    """RGBA16F copies of the gather's inputs: motion (both halves), color, and color_depth
    (colour with the depth in its alpha), rounded to nearest by NumPy."""
    motion = run.inputs["motion_sides"].download()
    color = run.inputs["color"].download()
    depth = run.inputs["depth"].download().reshape(color.shape[:2])
    # The background's depth lies past the largest half (65504): clamped there.
    color_depth = np.concatenate([color[..., :3], np.minimum(depth, 65504.0)[..., None]], axis=-1)
    height, width = color.shape[:2]
    return {
        name: mgl.texture((width, height), 4, image.astype(np.float16).tobytes(), dtype="f2")
        for name, image in {"motion": motion, "color": color, "color_depth": color_depth}.items()
    }


# glMemoryBarrier bits (GL 4.5): every blurlab pass ends with GL_ALL_BARRIER_BITS.
BARRIERS = {
    "all bits (as blurlab)": 0xFFFFFFFF,
    "texture fetch + image access": 0x00000008 | 0x00000020,
    "none (unsafe: timing only)": 0,
}


def barrier_costs(ctx, frame, runs: int) -> dict:
    """Part 5: what the barrier after each pass costs. A compute pass over one texel and one over
    the frame (read a texel, write a texel), each dispatched back to back with each of BARRIERS
    after it; "none" lets dispatches overlap and only bounds the gain."""
    mgl = ctx.moderngl()
    height, width = frame.color.shape[:2]
    program = mgl.compute_shader(
        "#version 450\nlayout(local_size_x = 16, local_size_y = 16) in;\n"
        "layout(binding = 0) uniform sampler2D source;\n"
        "layout(binding = 0, rgba32f) uniform writeonly image2D target;\n"
        "uniform ivec2 size;\n"
        "void main() { ivec2 p = ivec2(gl_GlobalInvocationID.xy);"
        " if (any(greaterThanEqual(p, size))) return;"
        " imageStore(target, p, texelFetch(source, p, 0) * 0.5); }"
    )
    source = mgl.texture((width, height), 4, frame.color.tobytes(), dtype="f4")
    target = mgl.texture((width, height), 4, dtype="f4")
    program["source"] = 0
    record: dict = {}
    for label, size in (("one texel", (1, 1)), ("the frame", (width, height))):
        groups = (-(-size[0] // 16), -(-size[1] // 16))
        for barrier_label, bits in BARRIERS.items():

            def dispatch(groups=groups, size=size, bits=bits):
                source.use(0)
                target.bind_to_image(0, read=False, write=True)
                program["size"] = size
                program.run(*groups)
                if bits:
                    mgl.memory_barrier(bits)

            one, in_a_row = dispatch_ms(ctx, mgl, dispatch, runs)
            key = f"{label}, {barrier_label}"
            record[key] = {"one_dispatch_ms": one, "back_to_back_ms": in_a_row}
            print(f"{key:52s} one dispatch {one:.4f} ms, back to back {in_a_row:.4f} ms")
    for item in (program, source, target):
        item.release()
    return record


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--parts", default=",".join(PARTS))
    parser.add_argument("--scene", default="teapot_pass", help="a built-in or failure scene")
    parser.add_argument("--json")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.split("x"))
    ctx = open_context(args.device)
    parts = set(args.parts.split(","))
    if parts - set(PARTS):
        parser.error(f"unknown parts {sorted(parts - set(PARTS))}; choose from {PARTS}")
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    frame = ctx.render(bl.scenes.get(args.scene), size)
    if "passes" in parts:
        record["passes"] = filter_passes(ctx, frame, args.runs)
        save(args.json, record)  # before moderngl shares the context
    if "fetch" in parts:
        record["fetch"] = fetch_paths(ctx, frame, args.runs)
    if "fetch_clamped" in parts:  # part 2 over McGuire's own NeighborMax (|vN| <= k)
        result = bl.blur(ctx, frame, FILTER_RUNS[1][1], **FILTER_RUNS[1][2])
        tiles = result.textures["neighbor_max"].download()
        record["fetch_clamped"] = fetch_paths(ctx, frame, args.runs, tiles)
    if "dispatch" in parts:
        record["dispatch"] = blurlab_or_moderngl(ctx, frame, args.runs)
    if "coverage" in parts:
        record["coverage"] = coverage_gather_constants(ctx, frame, args.runs)
    if "barriers" in parts:
        record["barriers"] = barrier_costs(ctx, frame, args.runs)
    if "coverage_costs" in parts:
        record["coverage_costs"] = coverage_costs(ctx, frame, args.runs)
    save(args.json, record)


if __name__ == "__main__":
    main()
