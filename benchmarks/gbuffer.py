"""G-buffer pass time of a built-in scene (default teapot_pass).

Reports the pass alone (GL timer query on a GPU, glFinish + wall clock on llvmpipe) and the whole
``ctx.render`` call as a Python caller sees it (matrices, pass, download of four buffers).
The first render is left out: it compiles shaders (llvmpipe JIT-compiles each variant).

    python benchmarks/gbuffer.py [--device gpu] [--size 1920x1080] [--runs 20] [--json out.json]
"""

from __future__ import annotations

import argparse
import time

import blurlab as bl

from common import describe, save, summarize


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--scene", default="teapot_pass", choices=bl.scenes.names())
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    device = int(args.device) if args.device.isdigit() else args.device
    width, height = (int(v) for v in args.size.split("x"))

    ctx = bl.Context(device)
    scene = bl.scenes.get(args.scene)
    for _ in range(2):
        ctx.render(scene, (width, height))  # compile and warm up
    passes, calls = [], []
    for _ in range(args.runs):
        start = time.perf_counter()
        frame = ctx.render(scene, (width, height))
        calls.append((time.perf_counter() - start) * 1e3)
        passes.append(frame.timings["gbuffer"].ms)
    clock = frame.timings["gbuffer"].clock
    triangles = sum(len(o.mesh.indices) for o in scene.objects)
    record = {
        **describe(ctx),
        "scene": args.scene,
        "size": f"{width}x{height}",
        "triangles": triangles,
        "gbuffer_pass": {**summarize(passes), "clock": clock},
        "render_call": {**summarize(calls), "clock": "wall"},
    }
    save(args.json, record)
    print(f"\n{record['date']}  {record['renderer']}")
    print(f"{args.scene}, {width}x{height}, {triangles} triangles, {args.runs} runs\n")
    print("| what | median ms | min ms | clock |")
    print("|---|---|---|---|")
    print(f"| G-buffer pass | {summarize(passes)['median_ms']:.3f} | {min(passes):.3f} | {clock} |")
    print(
        f"| ctx.render (pass + 4 downloads) | {summarize(calls)['median_ms']:.2f} | "
        f"{min(calls):.2f} | wall |"
    )


if __name__ == "__main__":
    main()
