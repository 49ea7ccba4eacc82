"""Upload and download throughput of a 1920x1080 RGBA float32 image (33.2 MB).

Paths measured:
- upload: glTextureSubImage2D from the NumPy array.
- download (sync): glGetTextureImage into a new NumPy array, one at a time.
- download (async, copy): downloads queued into persistently mapped pixel-pack buffers with
  fences, DEPTH in flight, each result copied into a new NumPy array.
- download (async, zero-copy): the same, the array being a read-only view of the mapped buffer.

Throughput is bytes / wall time per image (median over the runs; wall clock around each call,
glFinish included, so it is the time a Python caller waits). Prints a Markdown table.

    python benchmarks/transfer.py [--device auto|gpu|software|N] [--runs 20] [--json out.json]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import blurlab as bl

from common import describe, save, summarize


def timed(fn, runs: int) -> list[float]:
    samples = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        samples.append((time.perf_counter() - start) * 1e3)
    return samples


def pipelined(texture: bl.Texture, runs: int, depth: int, copy: bool) -> list[float]:
    """Per-image time when `depth` downloads are kept in flight."""
    in_flight = [texture.download_async() for _ in range(depth)]
    start = time.perf_counter()
    for _ in range(runs):
        result = in_flight.pop(0).result(copy=copy)
        in_flight.append(texture.download_async())
        del result
    for pending in in_flight:
        pending.result(copy=copy)
    per_image = (time.perf_counter() - start) * 1e3 / (runs + depth)
    return [per_image]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--depth", type=int, default=3, help="async downloads in flight")
    parser.add_argument("--json", default=None, help="also write the results here")
    args = parser.parse_args()
    device = int(args.device) if args.device.isdigit() else args.device
    width, height = (int(v) for v in args.size.split("x"))

    ctx = bl.Context(device)
    image = np.random.default_rng(0).random((height, width, 4), dtype=np.float32)
    megabytes = image.nbytes / 1e6
    texture = ctx.upload(image)
    ctx.finish()

    def upload():
        texture.upload(image)
        ctx.finish()

    assert np.array_equal(texture.download(), image)  # the measured paths move the real data
    rows = {
        "upload": summarize(timed(upload, args.runs)),
        "download (sync)": summarize(timed(texture.download, args.runs)),
        f"download (async, copy, {args.depth} in flight)": summarize(
            pipelined(texture, args.runs, args.depth, copy=True)
        ),
        f"download (async, zero-copy, {args.depth} in flight)": summarize(
            pipelined(texture, args.runs, args.depth, copy=False)
        ),
    }
    for row in rows.values():
        row["GB_per_s"] = megabytes / row["median_ms"]  # MB/ms = GB/s
        row["best_GB_per_s"] = megabytes / row["min_ms"]

    record = {**describe(ctx), "size": f"{width}x{height}", "megabytes": megabytes, "paths": rows}
    save(args.json, record)
    print(f"\n{record['date']}  {record['renderer']}  ({record['gl_version']})")
    print(f"{width}x{height} RGBA float32, {megabytes:.1f} MB, {args.runs} runs, wall clock\n")
    print("| path | median ms | GB/s (median) | GB/s (best) |")
    print("|---|---|---|---|")
    for name, row in rows.items():
        print(
            f"| {name} | {row['median_ms']:.2f} | {row['GB_per_s']:.2f} | "
            f"{row['best_GB_per_s']:.2f} |"
        )


if __name__ == "__main__":
    main()
