"""Resource use over long loops: CYCLES render + blur + readback cycles (every registered
single-frame method in turn, accumulation and stochastic excepted: they re-render many times)
and CONTEXTS context create/use/destroy cycles. Prints live GL objects, process memory (RSS)
and, where the driver reports it (NVIDIA: GL_NVX_gpu_memory_info), free video memory before and
after, and the time per cycle. A measurement, not a pass/fail test (tests/test_resources.py
asserts flatness at a tiny size).

    python benchmarks/reliability.py [--device auto|gpu|software|N] [--size 1920x1080]
        [--cycles 1000] [--contexts 100] [--json out.json]
"""

from __future__ import annotations

import argparse
import gc
import os
import time
import warnings

import numpy as np

import blurlab as bl

from common import describe, save


def rss_mib() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def snapshot(ctx) -> dict:
    gc.collect()
    ctx.finish()
    vram = ctx.memory()
    return {
        "live_objects": ctx.live_objects(),
        "rss_mib": round(rss_mib(), 1),
        "vram_available_mib": round(vram["available"] / 1024, 1) if vram else None,
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="320x180")
    parser.add_argument("--cycles", type=int, default=1000)
    parser.add_argument("--contexts", type=int, default=100)
    parser.add_argument("--json")
    args = parser.parse_args()
    device = int(args.device) if args.device.isdigit() else args.device
    size = tuple(int(v) for v in args.size.split("x"))
    ctx = bl.Context(device)
    scene = bl.scenes.teapot_pass()
    names = [n for n in bl.methods() if not bl.method(n).renders]

    def cycle(i):
        name = names[i % len(names)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = ctx.render(scene, size, instant=bl.method_instant(name, {}))
            color = bl.blur(ctx, frame, name).color
        assert np.isfinite(color).all()

    for i in range(50):
        cycle(i)
    before = snapshot(ctx)
    start = time.perf_counter()
    for i in range(args.cycles):
        cycle(i)
    per_cycle = (time.perf_counter() - start) * 1e3 / args.cycles
    after = snapshot(ctx)

    rss0 = rss_mib()
    start = time.perf_counter()
    for _ in range(args.contexts):
        other = bl.Context(device)
        other.upload(np.ones((size[1], size[0], 4), np.float32)).download()
        del other
    gc.collect()
    per_context = (time.perf_counter() - start) * 1e3 / args.contexts
    rss1 = rss_mib()

    record = {
        **describe(ctx),
        "size": list(size),
        "cycles": args.cycles,
        "ms_per_cycle": round(per_cycle, 2),
        "before": before,
        "after": after,
        "contexts": args.contexts,
        "ms_per_context": round(per_context, 2),
        "context_rss_mib": [round(rss0, 1), round(rss1, 1)],
        "gl_errors": ctx.gl_errors(),
    }
    save(args.json, record)
    print(f"device: {record['renderer']}; {size[0]}x{size[1]}")
    print("| loop | n | ms each | live objects before -> after | RSS MiB | free VRAM MiB |")
    print("|---|---|---|---|---|---|")
    print(
        f"| render+blur+readback | {args.cycles} | {per_cycle:.2f} | "
        f"{sum(before['live_objects'].values())} -> {sum(after['live_objects'].values())} | "
        f"{before['rss_mib']} -> {after['rss_mib']} | "
        f"{before['vram_available_mib']} -> {after['vram_available_mib']} |"
    )
    print(
        f"| context create/destroy | {args.contexts} | {per_context:.2f} | - | "
        f"{rss0:.1f} -> {rss1:.1f} | - |"
    )


if __name__ == "__main__":
    main()
