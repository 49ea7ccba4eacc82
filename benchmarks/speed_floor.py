"""Issue 19's figures in one run ("speed to the floor"), on one G-buffer of teapot_pass:

1. filters: McGuire 2012 (k = 20, S = 15) and Guertin 2014 per pass, compute and fragment
   (fragment / compute), each with the stored and the packed inputs (packed_inputs, docs/spec.md
   §19; the packing pass timed once), and packed with a half-float result (half_result), and a
   Python call (wall clock per untimed bl.blur over
   a loop, finished once) against its GPU time: over the first 20 calls (which note, then
   record, the dispatch plan: docs/spec.md §18) and in steady state over 200, with the CPU
   time of this process per call; then TileMax's work-group layouts (TILE_MAX_VARIANTS)
   at each --tile-max-k, on stored and packed motion, and whether they give the same bits;
2. bytes per pixel the filter cannot avoid (read colour, depth and motion once, write colour
   once), as stored and packed, and the share of the DRAM floor: those bytes at the
   bandwidth of a streaming pass (accumulate.comp over --bandwidth-size, 48 B per pixel)
   against the filter's GPU time;
3. sweep evaluations per second (blur + metrics reduced on the GPU, untimed, parameters
   cycling through k and S) with PSNR + SSIM (one gpu_mse_ssim pass against the prepared
   reference, as sweeps run), with PSNR + SSIM + FLIP, each read back per evaluation and in
   batches of --readback-batch (metrics.MetricQueue, docs/spec.md §6.3; the rows must be the
   same bits), and with PSNR + SSIM from gpu_mse_ssim of the two textures and from separate
   gpu_mse + gpu_ssim passes;
4. gpu_mse, gpu_ssim, gpu_mse_ssim, gpu_mse_ssim against a prepared reference and
   prepare_reference (each in every SSIM work-group layout, --ssim-layouts, tiles and strips),
   and gpu_flip: wall clock per call (with the scalar read back) and GPU time;
5. the G-buffer pass in steady state (after warm-up, targets from the context's pool) for each
   of --raster-scenes, against its rasterization floor on the same four float targets and a
   depth buffer (moderngl on blurlab's context): a clear + a draw that makes no fragment, a
   clear + a full-screen triangle writing constants, and the scene without shading (its
   geometry, transform only, constant outputs, then the background triangle); with triangle
   and fragment counts, and the first call on a fresh context split into shader build, mesh
   uploads, material textures, target allocation, first pass, second pass;
6. the three-pass floor ("still"): each filter, compute with packed inputs (and a half-float
   result), back to back on teapot_pass and on the same frame with its motion set to zero,
   where every tile's NeighborMax is 0 and every pixel leaves the reconstruct at its early exit
   (docs/spec.md §3.4 step 2), reading only its own texels: what the filter would cost if its
   taps were free, against the goal;
7. with --study, `blurlab study` (run_study, default scenes and grids, all three metrics) at
   --size, with the phases it times itself (phases.json): references, G-buffers, evaluations,
   images, charts, per-object table, HTML.

Medians over --runs; GL timer queries on a GPU, glFinish + wall clock on llvmpipe.

    python benchmarks/speed_floor.py [--device gpu] [--size 1920x1080] [--study] [--json f]
        [--parts filters,sweep,metrics,raster,still] [--ssim-layouts pixel16,column4,...]
        [--raster-scenes teapot_pass,textured_spin,vehicle]
"""

from __future__ import annotations

import argparse
import importlib
import itertools
import json
import re
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import blurlab as bl
from blurlab import metrics
from blurlab.methods.tile_filter import TILE_MAX_VARIANTS, tile_max_variant
from blurlab.render import (
    camera_matrices,
    gbuffer_pass,
    instant_time,
    render_targets,
    target_shapes,
)

from common import back_to_back_ms, describe, median_passes, open_context, save, spin_up

PARTS = ("filters", "sweep", "metrics", "raster", "still")  # what --parts can choose
GOALS_MS = {"reconstruct_mcguire2012": 0.035, "reconstruct_guertin2014": 0.040}  # issue 19
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


WAYS_OF_INPUTS = {  # label suffix -> the filter's options
    "": {"packed_inputs": False},
    " packed": {"packed_inputs": True},
    " packed half": {"packed_inputs": True, "half_result": True},  # RGBA16F result too
}


def table_header(*columns: str) -> None:
    """Prints a Markdown table's header after a blank line."""
    print("\n| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))


def filters(ctx, frame, runs: int) -> dict:
    """Each filter per backend with the stored inputs ("compute", "fragment"), with packed
    inputs ("compute packed", "fragment packed"; the frame is packed once, before timing) and
    with packed inputs and a half-float result ("compute packed half", "fragment packed half")."""
    out = {}
    table_header(
        "filter / backend", "per pass, ms", "GPU total, ms", "calls back to back, GPU ms",
        "Python call, first 20, ms (/ GPU)", "Python call, steady, ms", "its CPU, ms",
        "call / GPU",
    )  # fmt: skip
    for name, stored_params in FILTERS.items():
        out[name] = {}
        ways = itertools.product(bl.method(name).backends, WAYS_OF_INPUTS)
        for backend, suffix in ways:
            params = {**stored_params, **WAYS_OF_INPUTS[suffix]}
            label = backend + suffix
            medians, _ = median_passes(ctx, frame, name, runs, backend=backend, **params)
            total = sum(medians.values())
            # A Python call as a sweep makes it: untimed, the GPU finished once after the loop.
            # The first 20 include the call that only notes the parameters and the one that
            # records the plan (docs/spec.md §18), as the figures before 2026-11-24 05:00 did.
            first = untimed_calls(ctx, frame, name, backend, params, 20)
            # Then steady state, the plan recorded: wall clock and this process's CPU time.
            call, cpu = untimed_calls(ctx, frame, name, backend, params, max(runs, 200))
            # One timer around calls issued while the GPU is busy: no per-pass timers, no wait.
            queued = back_to_back_ms(
                ctx,
                lambda name=name, backend=backend, params=params: bl.blur(
                    ctx, frame, name, backend=backend, timed=False, **params
                ),
            )
            out[name][label] = {
                "passes_ms": medians,
                "total_ms": total,
                "back_to_back_ms": queued,
                "call_ms": call,
                "call_cpu_ms": cpu,
                "first_20_calls_ms": first[0],
            }
            passes = ", ".join(f"{p} {v:.4f}" for p, v in medians.items())
            print(
                f"| {name} / {label} | {passes} | {total:.4f} | {queued:.4f} | {first[0]:.4f} "
                f"({first[0] / total:.2f}x) | {call:.4f} | {cpu:.4f} | {call / total:.2f} |"
            )
        both = out[name]
        for suffix in WAYS_OF_INPUTS:
            if "fragment" + suffix in both:
                fragment, compute = both["fragment" + suffix], both["compute" + suffix]
                ratio = fragment["total_ms"] / compute["total_ms"]
                queued = fragment["back_to_back_ms"] / compute["back_to_back_ms"]
                both["fragment_over_compute" + suffix.replace(" ", "_")] = ratio
                both["fragment_over_compute_back_to_back" + suffix.replace(" ", "_")] = queued
                print(f"| {name}: fragment / compute{suffix} | | {ratio:.1f}x | {queued:.1f}x | |")
        packing = both["compute"]["total_ms"] / both["compute packed"]["total_ms"]
        both["stored_over_packed"] = packing
        print(f"| {name}: compute stored / packed | | {packing:.2f}x | | |")
    out["pack_inputs_ms"] = frame.timings["pack_inputs"].ms  # once per frame, first call
    print(f"| packing pass (once per frame) | | {out['pack_inputs_ms']:.4f} | | |")
    return out


def three_pass_floor(ctx, frame, runs: int) -> dict:
    """Item 6: each filter back to back (and per pass) on `frame` and on a still copy of it."""
    still = bl.Frame(
        color=frame.color,
        depth=frame.depth,
        motion=np.zeros_like(frame.motion),
        object_id=frame.object_id,
    )
    ways = {suffix.strip(): way for suffix, way in WAYS_OF_INPUTS.items() if way["packed_inputs"]}
    out = {}
    table_header(
        "filter / inputs", "goal, ms", "teapot_pass, back to back", "still frame, back to back",
        "still frame per pass", "floor / goal",
    )  # fmt: skip
    for name, filter_params in FILTERS.items():
        out[name] = {}
        for label, way in ways.items():
            params = {**filter_params, **way}
            row = {}
            for which, source in (("moving", frame), ("still", still)):
                call = lambda source=source, name=name, params=params: bl.blur(  # noqa: E731
                    ctx, source, name, timed=False, **params
                )
                row[f"{which}_back_to_back_ms"] = back_to_back_ms(ctx, call)
            row["still_passes_ms"], _ = median_passes(ctx, still, name, runs, **params)
            row["floor_over_goal"] = row["still_back_to_back_ms"] / GOALS_MS[name]
            out[name][label] = row
            passes = ", ".join(f"{p} {v:.4f}" for p, v in row["still_passes_ms"].items())
            print(
                f"| {name} / {label} | {GOALS_MS[name]} | {row['moving_back_to_back_ms']:.4f} | "
                f"{row['still_back_to_back_ms']:.4f} | {passes} | {row['floor_over_goal']:.2f}x |"
            )
    return out


def untimed_calls(ctx, frame, name, backend, params, calls: int) -> tuple[float, float]:
    """(wall ms, CPU ms of this process) per untimed bl.blur over `calls` calls in a loop, the
    GPU finished before and once after it. Where the CPU time is below the wall time, the GPU
    bounds the loop; on llvmpipe the CPU time includes the passes' work."""
    ctx.finish()
    start, cpu = time.perf_counter(), time.process_time()
    for _ in range(calls):
        bl.blur(ctx, frame, name, backend=backend, timed=False, **params)
    ctx.finish()
    cpu = time.process_time() - cpu
    return 1e3 * (time.perf_counter() - start) / calls, 1e3 * cpu / calls


def tile_max_variants(ctx, frame, runs: int, ks) -> dict:
    """TileMax's pass time for each work-group layout (TILE_MAX_VARIANTS) at each k, reading the
    stored motion (RG32F) and the packed motion + depth (RGBA16F), and whether each gives the
    default layout's bits. A layout only applies where a work group scans a tile: k > 8 px on a
    GPU, k > 32 px on llvmpipe (tile_filter.largest_tile_for_one_thread)."""
    record = {}
    print("\n| TileMax variant | k | stored motion, ms | packed motion, ms | same bits |")
    print("|---|---|---|---|---|")
    first_bits = {}  # (k, packed) -> the tiles of the first variant, the default
    for k in ks:
        for variant in TILE_MAX_VARIANTS:
            row = {"same_bits": True}
            for packed in (False, True):
                params = {"k": k, "samples": 15, "packed_inputs": packed}
                with tile_max_variant(variant):
                    times = []
                    for _ in range(runs + 2):
                        result = bl.blur(ctx, frame, "reconstruct_mcguire2012", **params)
                        times.append(result.timings["tile_max"].ms)
                    tiles = result.buffers["tile_max"]
                row["packed_ms" if packed else "stored_ms"] = statistics.median(times[2:])
                expected = first_bits.setdefault((k, packed), tiles)
                row["same_bits"] &= bool((tiles == expected).all())
            record[f"{variant} k={k}"] = row
            print(
                f"| {variant} | {k} | {row['stored_ms']:.4f} | {row['packed_ms']:.4f} | "
                f"{row['same_bits']} |"
            )
    return record


def subgroup_extensions(ctx) -> list[str] | None:
    """The GL extensions whose names mention subgroups (the TileMax variants *_subgroup fall
    back to the shared-memory reduction without GL_KHR_shader_subgroup); None without
    moderngl to ask."""
    try:
        return sorted(e for e in ctx.moderngl().extensions if "subgroup" in e.lower())
    except ImportError:
        return None


def streaming_bandwidth(ctx, size: tuple[int, int], runs: int) -> dict:
    """Bytes per second of accumulate.comp (reads a colour and a sum, writes the sum: 3 RGBA32F
    texels, 48 B per pixel) over images too large for the caches."""
    width, height = size
    color = ctx.empty((height, width, 4))
    total = ctx.empty((height, width, 4))
    step = ctx.shader_pass("passes/accumulate.comp")
    ms = gpu_ms(ctx, lambda: step.run({"color": color}, {"sum": total}, {"weight": 0.5}), runs)
    ctx.recycle(color, total)
    # The same pass over one pixel: what a dispatch costs by this clock with nearly no work, a
    # floor under each pass of a filter timed pass by pass.
    color, total = ctx.empty((1, 1, 4)), ctx.empty((1, 1, 4))
    one = gpu_ms(ctx, lambda: step.run({"color": color}, {"sum": total}, {"weight": 0.5}), runs)
    ctx.recycle(color, total)
    return {
        "size": f"{width}x{height}",
        "ms": ms,
        "gb_per_s": 48 * width * height / ms / 1e6,
        "one_pixel_dispatch_ms": one,
    }


def texel_bytes(texture) -> int:
    return texture.dtype.itemsize * texture.channels


def dram_floor(ctx, frame, filter_results: dict, bandwidth: dict, nominal_gbs) -> dict:
    """Bytes per pixel the filter cannot avoid (read its inputs once, write colour once), as
    stored and packed, and that traffic at the streaming and nominal bandwidths against the
    filters' compute GPU time."""
    textures = frame.textures
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False)
    output = {"output colour": texel_bytes(result.textures["color"])}
    half = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False, half_result=True)
    packed = {k: texel_bytes(textures[f"packed_{k}"]) for k in ("color", "motion_depth")}
    layouts = {
        "": {k: texel_bytes(textures[k]) for k in ("color", "depth", "motion")} | output,
        " packed": packed | output,
        " packed half": packed | {"output colour": texel_bytes(half.textures["color"])},
    }
    pixels = frame.color.shape[0] * frame.color.shape[1]
    record = {"bytes_per_pixel": {}, "total_bytes_per_pixel": {}, "filters": {}}
    rates = {"measured streaming": bandwidth["gb_per_s"]}
    if nominal_gbs:
        rates["nominal"] = nominal_gbs
    print(f"\nStreaming pass: {bandwidth['gb_per_s']:.0f} GB/s over {bandwidth['size']}")
    print(f"The same pass over one pixel: {bandwidth['one_pixel_dispatch_ms']:.4f} ms")
    for suffix, layout in layouts.items():
        per_pixel = sum(layout.values())
        inputs = suffix.strip() or "stored"
        record["bytes_per_pixel"][inputs] = layout
        record["total_bytes_per_pixel"][inputs] = per_pixel
        print(f"Bytes per pixel the filter cannot avoid, inputs {inputs}: {layout} = {per_pixel} B")
    print("\n| filter | inputs | bandwidth | DRAM floor, ms | filter GPU, ms | floor / filter |")
    print("|---|---|---|---|---|---|")
    for name, backends in filter_results.items():
        if not isinstance(backends, dict):
            continue  # pack_inputs_ms
        for suffix, layout in layouts.items():
            gpu = backends["compute" + suffix]["total_ms"]
            per_pixel = sum(layout.values())
            for label, gbs in rates.items():
                floor = per_pixel * pixels / (gbs * 1e6)
                record["filters"][f"{name}{suffix} ({label})"] = {
                    "bytes_per_pixel": per_pixel,
                    "floor_ms": floor,
                    "filter_ms": gpu,
                    "share": floor / gpu,
                }
                inputs = suffix.strip() or "stored"
                print(
                    f"| {name} | {inputs} | {label} {gbs:.0f} GB/s | {floor:.4f} | {gpu:.4f} | "
                    f"{floor / gpu:.0%} |"
                )
    return record


def sweep_rate(ctx, frame, reference, evaluations: int, batch: int) -> dict:
    """Evaluations per second as bl.sweep makes them (PSNR and SSIM from gpu_mse_ssim against the
    prepared reference), read back per evaluation and in batches of `batch` (MetricQueue,
    docs/spec.md §6.3, as bl.sweep's readback_batch), and for comparison from gpu_mse_ssim of the
    two textures and from the separate gpu_mse + gpu_ssim passes of before. The batched rows
    must equal the per-evaluation ones bit for bit ("same_rows")."""
    grid = list(itertools.product([10, 20, 40], [5, 9, 15, 25]))
    ways = {
        "PSNR + SSIM (prepared reference, as sweeps run)": ("prepared",),
        f"PSNR + SSIM, read back {batch} at a time": ("prepared", "deferred"),
        "PSNR + SSIM + FLIP (prepared reference)": ("prepared", "flip"),
        f"PSNR + SSIM + FLIP, read back {batch} at a time": ("prepared", "flip", "deferred"),
        "PSNR + SSIM, one pass, reference not prepared": ("fused",),
        "PSNR + SSIM, separate passes": ("separate",),
    }
    prepared = metrics.prepare_reference(ctx, reference.texture)
    batches = metrics.MetricBatches(ctx, batch)
    record = {"readback_batch": batch}
    print(
        "\n| sweep, untimed, reconstruct_mcguire2012 | evaluations / s | ms per evaluation "
        "| CPU ms per evaluation |"
    )
    print("|---|---|---|---|")
    for label, chosen in ways.items():

        def issue(i, chosen=chosen):
            """One evaluation: its values, or with "deferred" their indices in its batch."""
            k, s = grid[i % len(grid)]
            result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=k, samples=s, timed=False)
            color = result.textures["color"]
            if "deferred" in chosen:
                got = {"mse_ssim": batches.queue.mse_ssim(prepared, color)}
                if "flip" in chosen:
                    got["flip"] = batches.queue.flip(reference.texture, color)
                return got
            if "prepared" in chosen:
                got = {"mse_ssim": metrics.gpu_mse_ssim(ctx, prepared, color)}
            elif "fused" in chosen:
                got = {"mse_ssim": metrics.gpu_mse_ssim(ctx, reference.texture, color)}
            else:
                mse = metrics.gpu_mse(ctx, color, reference.texture)
                got = {"mse_ssim": (mse, metrics.gpu_ssim(ctx, reference.texture, color))}
            if "flip" in chosen:
                got["flip"] = metrics.gpu_flip(ctx, reference.texture, color)
            return got

        def run(first: int, count: int, chosen=chosen) -> list[dict]:
            """Evaluations first..first + count - 1; their rows (PSNR, SSIM, FLIP)."""
            rows = []
            for i in range(first, first + count):
                if "deferred" not in chosen:
                    rows.append(row_of(issue(i)))
                    continue
                for indices, values in batches.add(issue(i)):
                    rows.append(row_of({c: values[v] for c, v in indices.items()}))
            if "deferred" in chosen:
                for indices, values in batches.flush():
                    rows.append(row_of({c: values[v] for c, v in indices.items()}))
            return rows

        def row_of(got: dict) -> dict:
            mse, ssim = got["mse_ssim"]
            row = {"psnr": metrics.psnr_from_mse(mse), "ssim": ssim}
            if "flip" in got:
                row["flip"] = got["flip"]
            return row

        run(0, 3)
        ctx.finish()
        start, cpu = time.perf_counter(), time.process_time()
        rows = run(0, evaluations)
        rate = evaluations / (time.perf_counter() - start)
        cpu = 1e3 * (time.process_time() - cpu) / evaluations
        record[label] = {
            "evaluations_per_s": rate,
            "cpu_ms_per_evaluation": cpu,
            "last_row": rows[-1],
            "rows": rows[: len(grid)],
        }
        print(f"| {label} | {rate:.0f} | {1e3 / rate:.3f} | {cpu:.3f} |")
    pairs = {  # batched, per evaluation
        "": (f"PSNR + SSIM, read back {batch} at a time", next(iter(ways))),
        "_flip": (
            f"PSNR + SSIM + FLIP, read back {batch} at a time",
            "PSNR + SSIM + FLIP (prepared reference)",
        ),
    }
    for suffix, (now, before) in pairs.items():
        same = record[now]["rows"] == record[before]["rows"]
        speedup = record[now]["evaluations_per_s"] / record[before]["evaluations_per_s"]
        record["deferred_speedup" + suffix], record["same_rows" + suffix] = speedup, same
        print(f"| {now} / per evaluation | {speedup:.2f}x | same rows: {same} | |")
    prepared.release()
    return record


def against_prepared(ctx, reference, color, layout: str):
    """gpu_mse_ssim of `color` against `reference` prepared in `layout` (on the first call)."""
    prepared = []

    def call():
        if not prepared:
            prepared.append(metrics.prepare_reference(ctx, reference, layout))
        return metrics.gpu_mse_ssim(ctx, prepared[0], color)

    return call


def issued_time(ctx, against, color, runs: int, layout: str) -> dict:
    """issued_times' row: median GPU ms of one issue, and whether the values read back later
    equal gpu_mse_ssim's."""
    expected = metrics.gpu_mse_ssim(ctx, against, color, layout=layout)
    spin_up(lambda: metrics.gpu_mse_ssim(ctx, against, color, layout=layout))
    queue = metrics.MetricQueue(ctx)
    queue.mse_ssim(against, color, layout)  # compiled and warm before the clock
    samples = []
    for _ in range(runs):
        with ctx.timer() as timing:
            queue.mse_ssim(against, color, layout)
        samples.append(timing.ms)
    same = all(value == expected for value in queue.read())
    # Then 50 issued in a row behind busy work, one timer around them: a sweep's regime.
    queued = back_to_back_ms(
        ctx,
        lambda: queue.mse_ssim(against, color, layout),
        warm=lambda: metrics.gpu_mse_ssim(ctx, against, color, layout=layout),
    )
    same &= all(value == expected for value in queue.read())
    return {"gpu_ms": statistics.median(samples), "back_to_back_ms": queued, "same_value": same}


def issued_times(ctx, reference, color, runs: int, layouts) -> dict:
    """GPU time of the PSNR + SSIM pass alone, in each layout: each gpu_mse_ssim is issued into a
    metrics.MetricQueue inside the timer and read back after it (as bl.sweep does), so the timer
    holds the dispatch and not the wait for its scalar. Of a texture pair and of a prepared
    reference; the values read back must equal gpu_mse_ssim's."""
    record = {}
    print(
        "\n| PSNR + SSIM pass, issued, read back later | GPU ms | 50 back to back, GPU ms each "
        "| same value |\n|---|---|---|---|"
    )
    for layout in layouts:
        try:
            prepared = metrics.prepare_reference(ctx, reference, layout)
        except (RuntimeError, ValueError) as error:  # a layout the driver refuses: the rest
            record[layout] = {"error": str(error)}
            print(f"| {layout} | failed: {error} | |")
            continue
        for name, against in ((f"pair, {layout}", reference), (f"prepared, {layout}", prepared)):
            try:
                record[name] = issued_time(ctx, against, color, runs, layout)
            except (RuntimeError, ValueError) as error:
                record[name] = {"error": str(error)}
                print(f"| {name} | failed: {error} | |")
                continue
            row = record[name]
            print(
                f"| {name} | {row['gpu_ms']:.4f} | {row['back_to_back_ms']:.4f} | "
                f"{row['same_value']} |"
            )
        prepared.release()
    return record


def metric_times(ctx, frame, reference, runs: int, layouts) -> dict:
    """Wall clock per call (scalar read back) and GPU time of each metric on one image pair;
    gpu_ssim and gpu_mse_ssim in each SSIM work-group layout (metrics.SSIM_LAYOUTS)."""
    # `result` stays referenced to the end: dropped, its textures would go back to the pool,
    # and prepare_reference's pooled textures could be the very one `color` names.
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False)
    color = result.textures["color"]
    ways = {"gpu_mse": lambda: metrics.gpu_mse(ctx, color, reference.texture)}
    for layout in layouts:
        default = " (default)" if layout == metrics.SSIM_LAYOUT else ""
        default_prepared = " (default)" if layout == metrics.PREPARED_SSIM_LAYOUT else ""
        ways[f"gpu_ssim {layout}{default}"] = lambda layout=layout: metrics.gpu_ssim(
            ctx, reference.texture, color, layout=layout
        )
        ways[f"gpu_mse_ssim {layout}{default}"] = lambda layout=layout: metrics.gpu_mse_ssim(
            ctx, reference.texture, color, layout=layout
        )
        ways[f"gpu_mse_ssim, prepared reference, {layout}{default_prepared}"] = against_prepared(
            ctx, reference.texture, color, layout
        )
        ways[f"prepare_reference (once per reference), {layout}{default_prepared}"] = (
            lambda layout=layout: metrics.prepare_reference(
                ctx, reference.texture, layout
            ).release()
        )
    ways["gpu_flip"] = lambda: metrics.gpu_flip(ctx, reference.texture, color)
    record = {}
    print("\n| metric, one image pair | wall ms per call | GPU ms | value |\n|---|---|---|---|")
    for name, fn in ways.items():
        try:
            value = fn()
        except (RuntimeError, ValueError) as error:  # one layout the driver refuses: the rest
            record[name] = {"error": str(error)}
            print(f"| {name} | failed: {error} | | |")
            continue
        spin_up(fn)
        record[name] = {"wall_ms": wall_ms(fn, runs), "gpu_ms": gpu_ms(ctx, fn, runs)}
        record[name]["value"] = value
        r = record[name]
        values = value if isinstance(value, tuple) else () if value is None else (value,)
        shown = ", ".join(f"{v:.6f}" for v in values)
        print(f"| {name} | {r['wall_ms']:.4f} | {r['gpu_ms']:.4f} | {shown} |")
    record["issued"] = issued_times(ctx, reference.texture, color, runs, layouts)
    del result
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
    parser.add_argument(
        "--readback-batch", type=int, default=16, help="evaluations read back together (sweep)"
    )
    parser.add_argument("--bandwidth-size", default="4096x4096")
    parser.add_argument("--nominal-gbs", type=float, default=None, help="e.g. 3350 (H100 SXM)")
    parser.add_argument("--study", action="store_true", help="also time blurlab study")
    parser.add_argument(
        "--tile-max-k", default="20", help="comma-separated k at which to time TileMax's variants"
    )
    parser.add_argument(
        "--parts",
        default=",".join(PARTS),
        help=f"comma-separated subset of {','.join(PARTS)} (default: all; --study adds the study)",
    )
    parser.add_argument(
        "--ssim-layouts",
        default=",".join(metrics.SSIM_LAYOUTS),
        help="SSIM work-group layouts to time (keys of blurlab.metrics.SSIM_LAYOUTS, or tileHrN)",
    )
    parser.add_argument(
        "--raster-scenes",
        default="teapot_pass,textured_spin,vehicle",
        help="scenes of the G-buffer floor (comma-separated)",
    )
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    parts = set(args.parts.split(","))
    if parts - set(PARTS):
        parser.error(f"unknown parts {sorted(parts - set(PARTS))}; choose from {PARTS}")
    layouts = args.ssim_layouts.split(",")
    for layout in layouts:  # a candidate tile layout, timed before it earns a name
        candidate = re.fullmatch(r"tile(8|16|32)r(1|2|4|8)", layout)
        if layout not in metrics.SSIM_LAYOUTS and candidate:
            metrics.SSIM_LAYOUTS[layout] = (32, int(candidate[1]), int(candidate[2]))
    if set(layouts) - set(metrics.SSIM_LAYOUTS):
        parser.error(
            f"unknown SSIM layouts; choose from {list(metrics.SSIM_LAYOUTS)} or a candidate "
            "tileHrN (32 x H tiles, N rows an invocation: H 8, 16 or 32, N 1, 2, 4 or 8 <= H)"
        )
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    record = {**describe(ctx), "size": args.size, "runs": args.runs}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, medians of {args.runs} runs")
    if parts - {"raster"} or args.study:
        measure_filters_and_metrics(ctx, size, args, parts, layouts, record)
    record["subgroup_extensions"] = subgroup_extensions(ctx)
    print(f"\nsubgroup extensions (TileMax *_subgroup variants): {record['subgroup_extensions']}")
    save(args.json, record)  # before the moderngl part, which shares the GL context
    if "raster" in parts:
        try:
            record["raster"] = raster_floor(
                args.device, ctx, args.raster_scenes.split(","), size, args.runs
            )
        except ImportError as error:  # moderngl is not on every machine that measures
            print(f"\nrasterization floor left out: {error}")
    save(args.json, record)


def measure_filters_and_metrics(
    ctx, size: tuple[int, int], args, parts: set, layouts: list, record: dict
) -> None:
    """Items 1 to 4 and 6 (those in `parts`) and 7 of the module's list, on teapot_pass."""
    scene = bl.scenes.teapot_pass()
    frame = ctx.render(scene, size)
    reference = ctx.reference(scene, size, samples=64, progress=False)
    if "filters" in parts:
        record["filters"] = filters(ctx, frame, args.runs)
        ks = [int(k) for k in args.tile_max_k.split(",")]
        record["tile_max_variants"] = tile_max_variants(ctx, frame, args.runs, ks)
        bandwidth_size = tuple(int(v) for v in args.bandwidth_size.split("x"))
        record["bandwidth"] = streaming_bandwidth(ctx, bandwidth_size, args.runs)
        record["dram_floor"] = dram_floor(
            ctx, frame, record["filters"], record["bandwidth"], args.nominal_gbs
        )
    if "sweep" in parts:
        record["sweep"] = sweep_rate(ctx, frame, reference, args.evaluations, args.readback_batch)
    if "metrics" in parts:
        record["metrics"] = metric_times(ctx, frame, reference, args.runs, layouts)
    if "still" in parts:
        record["three_pass_floor"] = three_pass_floor(ctx, frame, args.runs)
    if args.study:
        record["study"] = study_phases(ctx, size)


if __name__ == "__main__":
    main()
