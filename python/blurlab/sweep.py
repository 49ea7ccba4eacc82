"""Sweeps: scenes × methods × parameter grids → one row per evaluation, in a pandas DataFrame.

Each scene's G-buffer is rendered once per instant its methods need and its reference once;
each evaluation runs the method, reduces the squared error against the reference on the GPU
(PSNR from a scalar readback), and, if asked, computes SSIM and FLIP on the CPU. Rows are
appended to a CSV file as they are made, so an interrupted sweep keeps every finished row and
a rerun with the same file skips them.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import pandas as pd

from . import metrics as m
from .accumulation import default_reference_samples
from .context import Context
from .methods import blur, method, method_instant, methods
from .render import check_shutter
from .scene import Scene

# Parameter grids of `blurlab study`: sensible ranges, small enough for llvmpipe. A grid is a
# {param: [values]} product, or a list of them (their union): the filter options each get one
# point beside the default configuration instead of multiplying the k × S product.
_OPTIONS_AT_DEFAULT = [
    {"k": [20], "samples": [15], "jitter_tiles": [1]},
    {"k": [20], "samples": [15], "adaptive_samples": [1]},
    {"k": [20], "samples": [15], "early_exit": [2.0]},
]
DEFAULT_GRIDS: dict[str, dict[str, list] | list[dict[str, list]]] = {
    "reconstruct_mcguire2012": [
        {"k": [10, 20, 40], "samples": [5, 9, 15, 25]},
        *_OPTIONS_AT_DEFAULT,
    ],
    "reconstruct_guertin2014": [{"k": [20], "samples": [9, 15, 25]}, *_OPTIONS_AT_DEFAULT],
    "reconstruct_urho3d": {"k": [20], "samples": [9, 15]},
    "gather_weighted": {},
    "gather_box": {"taps": [5, 10, 20]},
    "camera_only": {"taps": [10]},
    "accumulation": {"samples": [4, 8, 16]},
    "stochastic": {"slices": [2, 4, 8]},
}
# trail blends a sequence of frames; a single shutter has none to blend, so it is not swept.
SINGLE_FRAME_METHODS = tuple(DEFAULT_GRIDS)
METRICS = ("psnr", "ssim", "flip")


def grid_points(grid) -> list[dict]:
    """Every combination of a {param: [values]} grid, in a stable order; for a list of grids,
    the points of each in turn, each point once."""
    if not isinstance(grid, Mapping):
        points = []
        for part in grid:
            points += [p for p in grid_points(part) if p not in points]
        return points
    keys = sorted(grid)
    return [
        dict(zip(keys, values, strict=True))
        for values in itertools.product(*(grid[k] for k in keys))
    ]


def grid_keys(grid) -> set[str]:
    """The parameter names a grid (or a list of grids) sets."""
    return set(grid) if isinstance(grid, Mapping) else set().union(*(set(g) for g in grid))


def middle_point(grid) -> dict:
    """The configuration that stands for a method in image grids: the middle of each list of
    its (first) grid."""
    grid = grid if isinstance(grid, Mapping) else (grid[0] if grid else {})
    return {k: v[len(v) // 2] for k, v in grid.items()}


def _scene(item) -> Scene:
    from . import scenes

    return scenes.get(item) if isinstance(item, str) else item


def sweep(
    ctx: Context,
    scenes: Iterable,
    methods_and_grids=None,
    size=(640, 360),
    shutter=None,
    reference_samples: int | None = None,
    metrics: Sequence[str] = METRICS,
    out: str | Path | None = None,
    progress: bool = True,
    backends: Mapping[str, str] | None = None,
    repeats: int = 3,
) -> pd.DataFrame:
    """Evaluates every method at every point of its grid on every scene.

    `methods_and_grids`: a list of method names (default grids), a {name: grid} mapping, or
    None for every single-frame method with its default grid. `reference_samples`: N of each
    scene's reference; None picks max(64, 2 × the longest motion in pixels), at most 1024.
    `out`: a CSV file that rows are appended to as they finish; rows already in it are
    skipped. Each pass time is the median of `repeats` runs, all configurations of a scene
    timed back to back before any error is computed (a GPU left idle while the CPU computes
    SSIM and FLIP clocks down).
    """
    if not isinstance(ctx, Context):
        raise TypeError("blurlab.sweep needs a blurlab Context")
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"blurlab.sweep: repeats must be an integer >= 1, not {repeats!r}")
    unknown = set(metrics) - set(METRICS)
    if unknown:
        raise ValueError(f"blurlab.sweep: unknown metrics {sorted(unknown)}; choose from {METRICS}")
    if methods_and_grids is None:
        methods_and_grids = SINGLE_FRAME_METHODS
    if not isinstance(methods_and_grids, Mapping):
        methods_and_grids = {name: DEFAULT_GRIDS.get(name, {}) for name in methods_and_grids}
    for name, grid in methods_and_grids.items():
        method(name)  # raises for unknown names
        if name == "trail":
            raise ValueError("blurlab.sweep: trail needs a frame sequence; it is not swept")
        for key in grid_keys(grid):
            if key not in method(name).params:
                raise ValueError(f"blurlab.sweep: {name} has no parameter {key!r}")
    scene_list = [_scene(s) for s in scenes]
    if not scene_list:
        raise ValueError("blurlab.sweep: no scenes")
    path = Path(out) if out is not None else None
    if path is not None and path.suffix.lower() != ".csv":
        raise ValueError(f"blurlab.sweep: results go to a .csv file (appendable), not {path.name}")
    done = _finished_keys(path)
    info = ctx.info()
    width, height = size
    jobs = [
        (scene, name, point)
        for scene in scene_list
        for name, grid in methods_and_grids.items()
        for point in grid_points(grid)
    ]
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(jobs), desc="sweep", unit="evaluation")
    cache: dict = {}
    warmed: set = set()
    pending = []
    for scene, name, point in jobs:
        backend = (backends or {}).get(name)
        key = _key(scene.name, name, backend or method(name).backends[0], point, size)
        if key in done:
            if bar:
                bar.update()
            continue
        pending.append((scene, name, point, backend, key))
    for scene in scene_list:
        here = [job for job in pending if job[0] is scene]
        # Timing first, every configuration back to back: the GPU stays busy, so its clocks
        # stay up. Computing SSIM and FLIP between runs left it idle long enough to clock
        # down, and single runs after that were several times slower on the H100.
        timings = {}
        for _, name, point, backend, key in here:
            frame, reference = _scene_inputs(
                ctx, scene, name, point, size, shutter, reference_samples, cache
            )
            if (name, backend) not in warmed:  # compile (and, on llvmpipe, JIT) before timing
                blur(ctx, frame, name, backend, **point)
                warmed.add((name, backend))
            runs = []
            for _ in range(repeats):
                result = blur(ctx, frame, name, backend, **point)
                runs.append({p: t.ms for p, t in result.timings.items()})
                clock = result.clock
                del result  # back to the pool before the next run
            timings[key] = (runs, clock)
        # Then the error of each configuration, one untimed run each.
        for _, name, point, backend, key in here:
            frame, reference = _scene_inputs(
                ctx, scene, name, point, size, shutter, reference_samples, cache
            )
            runs, clock = timings[key]
            result = blur(ctx, frame, name, backend, timed=False, **point)
            row = {
                "scene": scene.name,
                "method": name,
                "backend": result.backend,
                "params": json.dumps(point, sort_keys=True),
                **{f"param_{k}": v for k, v in point.items()},
                **{f"ms_{p}": statistics.median(r[p] for r in runs) for p in runs[0]},
                "total_ms": statistics.median(sum(r.values()) for r in runs),
                "repeats": repeats,
                "clock": clock,
                "psnr": m.psnr_from_mse(
                    m.gpu_mse(ctx, result.textures["color"], reference.texture)
                ),
            }
            if "ssim" in metrics or "flip" in metrics:
                color, ref = result.color, reference.color
                if "ssim" in metrics:
                    row["ssim"] = m.ssim(ref, color)
                if "flip" in metrics:
                    row["flip"] = m.flip(ref, color)
            row.update(
                {
                    "device": info["device"],
                    "renderer": info["renderer"],
                    "width": width,
                    "height": height,
                    "reference_samples": reference.samples,
                    "shutter": json.dumps(list(frame.shutter)),
                }
            )
            del result  # its textures go back to the pool before the next evaluation
            if path is not None:
                _append(path, row)
            done[key] = row
            if bar:
                bar.update()
    if bar:
        bar.close()
    rows = list(done.values())
    table = pd.DataFrame(rows)
    keys = {
        _key(s.name, n, (backends or {}).get(n) or method(n).backends[0], p, size)
        for s, n, p in jobs
    }
    if len(table):
        table = table[
            [
                _key(
                    r["scene"],
                    r["method"],
                    r["backend"],
                    json.loads(r["params"]),
                    (r["width"], r["height"]),
                )
                in keys
                for r in rows
            ]
        ]
    return table.reset_index(drop=True)


def _scene_inputs(ctx, scene, name, point, size, shutter, reference_samples, cache):
    """The frame at the method's instant and the scene's reference, each made once."""
    instant = method_instant(name, point)
    frames = cache.setdefault(("frames", id(scene)), {})
    if instant not in frames:
        frames[instant] = ctx.render(scene, size, shutter, instant=instant)
    frame = frames[instant]
    if ("reference", id(scene)) not in cache:
        n = reference_samples
        if n is None:
            n = default_reference_samples(frame)
        cache[("reference", id(scene))] = ctx.reference(
            scene,
            size,
            check_shutter(scene.shutter if shutter is None else shutter),
            samples=n,
            progress=False,
        )
    return frame, cache[("reference", id(scene))]


def _key(scene: str, name: str, backend: str, point: dict, size) -> tuple:
    return (scene, name, backend, json.dumps(point, sort_keys=True), int(size[0]), int(size[1]))


def _finished_keys(path: Path | None) -> dict:
    if path is None or not path.exists() or path.stat().st_size == 0:
        return {}
    table = pd.read_csv(path)
    done = {}
    for row in table.to_dict("records"):
        row = {k: v for k, v in row.items() if not (isinstance(v, float) and math.isnan(v))}
        done[
            _key(
                row["scene"],
                row["method"],
                row["backend"],
                json.loads(row["params"]),
                (row["width"], row["height"]),
            )
        ] = row
    return done


def _append(path: Path, row: dict) -> None:
    """Appends one row; a new column (a method with other passes) rewrites the file once."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.exists() and path.stat().st_size > 0:
        with path.open(newline="") as f:
            header = next(csv.reader(f))
        if set(row) <= set(header):
            with path.open("a", newline="") as f:
                csv.DictWriter(f, header).writerow(row)
            return
        table = pd.concat([pd.read_csv(path), pd.DataFrame([row])], ignore_index=True)
        tmp = path.with_suffix(".csv.tmp")
        table.to_csv(tmp, index=False)
        tmp.replace(path)
        return
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, list(row))
        writer.writeheader()
        writer.writerow(row)


def sweep_methods() -> list[str]:
    """Registered methods that a single-shutter sweep can evaluate."""
    return [n for n in methods() if n != "trail"]
