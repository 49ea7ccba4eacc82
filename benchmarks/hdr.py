"""HDR scenes: every single-frame method x the HDR metrics, and the time each method takes.

Each method runs once at its default parameters on each HDR scene (bl.scenes.names("hdr")),
timed by bl.sweep (median of --repeats runs, the device's clock); its image is then scored
against the converged reference with the HDR metrics (docs/spec.md §6.2) and with clipped PSNR
for contrast. The metrics run on the CPU in --workers processes while the GPU goes on to the
next scene (HDR-FLIP at 1920x1080 takes a minute or more per image). Prints a table a scene and
writes CSV, markdown and (--json, for benchmarks/gpu.sh) JSON with the device that measured.

    python benchmarks/hdr.py [--device gpu] [--size 1920x1080] [--out FOLDER] [--images FOLDER]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import re
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd

import blurlab as bl
from blurlab import metrics
from blurlab.studies.sweep import sweep_methods

from common import describe, open_context, save

COLUMNS = ["hdr_flip", "psnr_tm", "ssim_tm", "log_lum_error", "energy_ratio", "psnr", "total_ms"]


def score(reference: np.ndarray, image: np.ndarray) -> dict:
    """Every HDR metric, the exposure, and the clipped PSNR that cannot see the highlights."""
    return {**metrics.hdr_scores(reference, image), "psnr": metrics.psnr(reference, image)}


def _append(path: Path, timing, scores: dict) -> None:
    """One finished row (scene, method, time, scores) appended to the partial CSV."""
    row = pd.DataFrame([{"scene": timing["scene"], "method": timing.name, **scores}])
    row["total_ms"] = timing["total_ms"]
    row.to_csv(path, mode="a", header=not path.exists(), index=False)


def _markdown(table: pd.DataFrame) -> str:
    """A markdown table of `table` (its index first), numbers to 4 significant digits."""
    columns = [table.index.name or "", *table.columns]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for index, row in table.iterrows():
        cells = [f"{v:.4g}" if isinstance(v, float) else str(v) for v in row]
        lines.append("| " + " | ".join([str(index), *cells]) + " |")
    return "\n".join(lines)


STOPS = (0, -10)  # the metrics' exposure, and 10 stops darker to see inside the highlights
COLUMNS_PER_ROW = 5


def _image_figure(path: Path, title: str, reference: np.ndarray, images: dict) -> None:
    """The reference and every method's image, tone-mapped at the reference's exposure and at
    STOPS darker, pixels shown 2x as they are (nearest); a 256-colour PNG, small for docs/."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    exposure = metrics.exposure(reference)
    panels = {"reference": reference, **images}
    rows = -(-len(panels) // COLUMNS_PER_ROW)
    height, width = reference.shape[:2]
    inches = (2 * width / 100, 2 * height / 100 + 0.18)
    fig, axes = plt.subplots(
        rows * len(STOPS),
        COLUMNS_PER_ROW,
        figsize=(inches[0] * COLUMNS_PER_ROW, inches[1] * rows * len(STOPS) + 0.3),
        squeeze=False,
    )
    for ax in axes.ravel():
        ax.axis("off")
    for k, stop in enumerate(STOPS):
        for i, (name, image) in enumerate(panels.items()):
            ax = axes[k * rows + i // COLUMNS_PER_ROW, i % COLUMNS_PER_ROW]
            ax.imshow(metrics.tone_map(image, exposure * 2.0**stop), interpolation="nearest")
            label = name.replace("reconstruct_", "")
            ax.set_title(label + (f" ({stop:+d} stops)" if stop else ""), fontsize=7)
    fig.suptitle(
        f"{title}: tone-mapped (Reinhard per channel, sRGB) at exposure {exposure:.3g}, "
        f"the reference's, and {STOPS[1]:+d} stops",
        fontsize=8,
    )
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    plt.close(fig)
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.open(buffer).convert("RGB").quantize(256).save(path, optimize=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="160x90", help="WxH (160x90: the CI size)")
    parser.add_argument("--scenes", default=",".join(bl.scenes.names("hdr")))
    parser.add_argument("--methods", default=",".join(sweep_methods()))
    parser.add_argument("--repeats", type=int, default=3)
    # The cores this process may run on (a container's, not the host's), one metric process each.
    parser.add_argument("--workers", type=int, default=len(os.sched_getaffinity(0)))
    parser.add_argument(
        "--out",
        default=None,
        help="folder for CSV and markdown (default: beside --json, else benchmarks/results)",
    )
    parser.add_argument("--json", default=None)
    parser.add_argument("--images", default=None, help="one tone-mapped image grid a scene")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    size = (width, height)
    ctx = open_context(args.device)
    record = {**describe(ctx), "size": args.size, "repeats": args.repeats}
    names = args.methods.split(",")
    start = time.perf_counter()
    device = "llvmpipe" if ctx.software else re.sub(r"[^a-z0-9]+", "-", record["renderer"].lower())
    stem = f"{record['date']}-{device.strip('-')[:24]}-hdr-{args.size}"
    folder = Path(args.out or (Path(args.json).parent if args.json else "benchmarks/results"))
    folder.mkdir(parents=True, exist_ok=True)
    # Rows are written as they finish, so a run cut short (a time limit) keeps what it made.
    partial = folder / f"{stem}-partial.csv"
    partial.unlink(missing_ok=True)
    timing_rows, pending = [], []
    # Spawned workers: a fork would copy the GL context's threads.
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(args.workers, mp_context=spawn) as pool:
        for scene_name in args.scenes.split(","):
            scene = bl.scenes.get(scene_name)
            table = bl.sweep(
                ctx,
                [scene],
                {name: {} for name in names},
                size,
                metrics=("psnr",),
                repeats=args.repeats,
                progress=False,
            )
            timing_rows.append(table)
            timed = table.set_index("method")
            samples = int(table["reference_samples"].iloc[0])
            reference = ctx.reference(scene, size, samples=samples, progress=False).color
            images = {}
            for name in names:
                frame = ctx.render(scene, size, instant=bl.method_instant(name, {}))
                images[name] = bl.blur(ctx, frame, name, timed=False).color
                future = pool.submit(score, reference, images[name])
                future.add_done_callback(
                    lambda f, row=timed.loc[name]: _append(partial, row, f.result())
                )
                pending.append((scene_name, name, future))
            if args.images:
                path = Path(args.images) / f"{scene_name}.png"
                _image_figure(path, f"{scene_name}, {args.size}", reference, images)
            print(f"{scene_name}: timed and rendered ({time.perf_counter() - start:.0f} s)")
        scores = [{"scene": s, "method": n, **f.result()} for s, n, f in pending]
    record["seconds"] = round(time.perf_counter() - start, 1)
    timings = pd.concat(timing_rows)[["scene", "method", "total_ms", "clock", "reference_samples"]]
    table = pd.DataFrame(scores).merge(timings, on=["scene", "method"])
    print(f"\n{record['date']}  {record['renderer']}  {args.size}  ({record['seconds']} s)")
    markdown = [
        f"# HDR scenes: methods x HDR metrics ({record['renderer']}, {args.size}, "
        f"{record['date']})",
        "",
        "Each method at its default parameters; `total_ms` = median of "
        f"{args.repeats} runs by `{table['clock'].iloc[0]}`. psnr is clipped to [0, 1] "
        "(the LDR metric), for contrast.",
    ]
    for scene_name, rows in table.groupby("scene", sort=False):
        shown = rows.set_index("method")[COLUMNS].sort_values("hdr_flip")
        text = shown.to_string(float_format=lambda v: f"{v:.4g}")
        exposure = rows["exposure"].iloc[0]
        samples = rows["reference_samples"].iloc[0]
        print(f"\n{scene_name} (exposure {exposure:.4g}, reference N = {samples})\n{text}")
        markdown += [
            "",
            f"## {scene_name}",
            "",
            f"Tone-mapping exposure {exposure:.4g}; reference N = {samples}.",
            "",
            _markdown(shown),
        ]
    table.to_csv(folder / f"{stem}.csv", index=False)
    partial.unlink(missing_ok=True)
    (folder / f"{stem}.md").write_text("\n".join(markdown) + "\n")
    print(f"\nwrote {folder / stem}.csv and .md")
    record["rows"] = json.loads(table.to_json(orient="records"))
    save(args.json, record)


if __name__ == "__main__":
    main()
