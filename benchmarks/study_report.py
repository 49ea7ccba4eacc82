"""The study report's pictures at 1080p without a 1080p GPU run (issue 19): each scene's
reference and every default method's image (middle of its grid) rendered at --render-size,
enlarged (bicubic, per channel) to --size, then written by the study's own writer
(blurlab.studies.study.write_pictures: full-size images, error maps, colour bar, crops, image
grid) on its thread pool. The pictures are CPU work, so llvmpipe measures them as a GPU
machine would run them; wall and CPU seconds per scene.

    python benchmarks/study_report.py [--size 1920x1080] [--scenes teapot_pass] [--json f]
"""

from __future__ import annotations

import argparse
import concurrent.futures
import importlib
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

import blurlab as bl
from blurlab.methods import method_instant

from common import describe, open_context, save

study = importlib.import_module("blurlab.studies.study")
sweep = importlib.import_module("blurlab.studies.sweep")


def enlarged(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    channels = [
        np.asarray(Image.fromarray(np.ascontiguousarray(image[..., c])).resize(size, Image.BICUBIC))
        for c in range(image.shape[2])
    ]
    return np.stack(channels, axis=-1).astype(np.float32)


def scene_images(ctx, name: str, render_size, size, samples: int):
    scene = bl.scenes.get(name)
    reference = ctx.reference(scene, render_size, samples=samples, progress=False).color
    images = {}
    for method_name, grid in sweep.default_grids().items():
        point = sweep.middle_point(grid)
        frame = ctx.render(scene, render_size, instant=method_instant(method_name, point))
        images[method_name] = enlarged(bl.blur(ctx, frame, method_name, **point).color, size)
    return enlarged(reference, size), images


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--render-size", default="480x270")
    parser.add_argument("--scenes", nargs="+", default=["teapot_pass"])
    parser.add_argument("--samples", type=int, default=32, help="reference sub-frames")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    render_size = tuple(int(v) for v in args.render_size.split("x"))
    record = {**describe(ctx), "size": args.size, "render_size": args.render_size}
    record["threads"] = min(8, os.cpu_count() or 1)
    print(f"\n| report pictures at {args.size}, scene | methods | wall s | CPU s | MB |")
    print("|---|---|---|---|---|")
    for name in args.scenes:
        reference, images = scene_images(ctx, name, render_size, size, args.samples)
        with tempfile.TemporaryDirectory() as folder:
            start, cpu = time.perf_counter(), time.process_time()
            with concurrent.futures.ThreadPoolExecutor(record["threads"]) as pool:
                _, encodes = study.write_pictures(name, reference, images, Path(folder), pool)
                for encode in encodes:
                    encode.result()
            wall, cpu = time.perf_counter() - start, time.process_time() - cpu
            megabytes = sum(p.stat().st_size for p in Path(folder).iterdir()) / 1e6
        record[name] = {"methods": len(images), "wall_s": wall, "cpu_s": cpu, "mb": megabytes}
        print(f"| {name} | {len(images)} | {wall:.2f} | {cpu:.2f} | {megabytes:.1f} |")
    save(args.json, record)


if __name__ == "__main__":
    main()
