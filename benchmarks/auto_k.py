"""k="auto" against every fixed k: does the rule (python/blurlab/methods/tile_filter.py
auto_k) lose more than 0.1 dB to the best fixed k on any scene? Every built-in and failure
scene, every tile filter that offers "auto", PSNR against the scene's reference (N chosen as
sweeps choose it). Prints one row per scene and filter: the best fixed k and its PSNR, the k
the rule chose and its PSNR, and the loss.

    python benchmarks/auto_k.py [--device gpu] [--size 1920x1080]
"""

from __future__ import annotations

import argparse
import json

import blurlab as bl
from blurlab.studies.sweep import sweep

from common import describe, open_context, save

FIXED_K = [4, 8, 12, 16, 20, 24, 32, 40, 48, 64, 80, 96, 128]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    ctx = open_context(args.device)
    size = tuple(int(v) for v in args.size.split("x"))
    filters = [n for n in bl.methods() if bl.method(n).params.get("k", None) is not None]
    filters = [n for n in filters if bl.method(n).params["k"].auto is not None]
    scene_names = bl.scenes.names() + bl.scenes.names("failure")
    grids = {name: {"k": [*FIXED_K, "auto"]} for name in filters}
    table = sweep(ctx, scene_names, grids, size, metrics=("psnr",), progress=False, repeats=1)
    record = {**describe(ctx), "size": args.size, "fixed_k": FIXED_K, "rows": []}
    print(f"\n{record['date']}  {record['renderer']}  {args.size}, samples 15 throughout")
    print("\n| scene | filter | best fixed k | its PSNR | auto k | auto PSNR | auto − best (dB) |")
    print("|---|---|---|---|---|---|---|")
    losses = []
    for (scene, name), rows in table.groupby(["scene", "method"], sort=False):
        points = [json.loads(p) for p in rows["params"]]
        fixed = rows[[p["k"] != "auto" for p in points]]
        auto = rows[[p["k"] == "auto" for p in points]].iloc[0]
        best = fixed.sort_values("psnr", ascending=False).iloc[0]
        best_k = json.loads(best["params"])["k"]
        loss = auto["psnr"] - best["psnr"]
        losses.append(loss)
        auto_k = json.loads(auto["auto_k"])
        record["rows"].append(
            {
                "scene": scene,
                "method": name,
                "best_k": best_k,
                "best_psnr": best["psnr"],
                "auto_k": auto_k,
                "auto_psnr": auto["psnr"],
                "psnr_by_k": dict(
                    zip([json.loads(p)["k"] for p in rows["params"]], rows["psnr"], strict=True)
                ),
            }
        )
        short = name.replace("reconstruct_", "")
        print(
            f"| {scene} | {short} | {best_k} | {best['psnr']:.2f} | {auto_k} | "
            f"{auto['psnr']:.2f} | {loss:+.2f} |"
        )
    within = sum(loss >= -0.1 for loss in losses)
    print(f"\nauto within 0.1 dB of the best fixed k on {within} of {len(losses)} (scene, filter)")
    median = sorted(losses)[len(losses) // 2]
    print(f"median auto − best: {median:+.2f} dB, worst {min(losses):+.2f} dB")
    # Against today's default k = 20: would "auto" be the better default?
    default_k = bl.method(filters[0]).params["k"].default
    gains = sorted(r["auto_psnr"] - r["psnr_by_k"][default_k] for r in record["rows"])
    better = sum(g > 0.05 for g in gains)
    print(
        f"auto − k = {default_k}: median {gains[len(gains) // 2]:+.2f} dB, "
        f"worst {gains[0]:+.2f}, best {gains[-1]:+.2f}; better on {better} of {len(gains)}"
    )
    save(args.json, record)


if __name__ == "__main__":
    main()
