"""Real content: the Khronos glTF sample models in ../shared/assets/gltf, each loaded, rendered
and put through the study; the pictures and tables of docs/content.md.

    python benchmarks/content.py [--size 640x360] [--device auto] [--out out/content]
        [--pictures docs/content]

Writes, per model, its frame and motion pictures (into --pictures), the study's report and
results.csv (into --out), and prints a markdown table: per model and method, the best PSNR
and the time of that configuration, with the device.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import blurlab as bl
from blurlab.cli import parse_size
from blurlab.studies import plots
from blurlab.studies.study import run_study

from common import describe, open_context

ASSETS = Path(__file__).resolve().parents[2] / "shared" / "assets" / "gltf"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=parse_size, default="640x360")
    parser.add_argument("--device", default="auto")
    parser.add_argument("--out", default="out/content")
    parser.add_argument("--pictures", default="docs/content")
    args = parser.parse_args()
    models = sorted(ASSETS.glob("*/*.gltf")) + sorted(ASSETS.glob("*/*.glb"))
    if not models:
        print(f"no sample models in {ASSETS}", file=sys.stderr)
        return 1
    ctx = open_context(args.device)
    size = args.size
    pictures = Path(args.pictures)
    pictures.mkdir(parents=True, exist_ok=True)
    print(f"device: {describe(ctx)}; {size[0]}x{size[1]}")
    print("\n| model | objects | triangles | shutter (s) | max \\|M\\| px | moving pixels |")
    print("|---|---|---|---|---|---|")
    for path in models:
        scene = bl.scenes.gltf(path, size_hint=size)
        frame = ctx.render(scene, size)
        speed = np.linalg.norm(frame.motion, axis=-1)
        triangles = sum(len(o.mesh.indices) for o in scene.objects)
        bl.io.write(pictures / f"{path.stem}_frame.png", frame.color)
        bl.io.write(pictures / f"{path.stem}_motion.png", plots.motion_picture(frame.motion))
        t0, t1 = scene.shutter
        print(
            f"| {path.name} | {len(scene.objects)} | {triangles} | {t0:.3f}–{t1:.3f} | "
            f"{speed.max():.1f} | {(speed >= 1).mean():.1%} |"
        )
    start = time.perf_counter()
    out = Path(args.out)
    run_study(ctx, [str(p) for p in models], size=size, out=out, progress=False)
    print(f"\nstudy of {len(models)} models: {time.perf_counter() - start:.0f} s")
    import pandas as pd

    table = pd.read_csv(out / "results.csv")
    print("\n| model | method | best PSNR (dB) | its SSIM | its FLIP | its ms | parameters |")
    print("|---|---|---|---|---|---|---|")
    for (scene, method_name), rows in table.groupby(["scene", "method"], sort=True):
        best = rows.sort_values("psnr", ascending=False).iloc[0]
        print(
            f"| {scene} | {method_name} | {best['psnr']:.2f} | {best['ssim']:.4f} | "
            f"{best['flip']:.4f} | {best['total_ms']:.3f} | `{best['params']}` |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
