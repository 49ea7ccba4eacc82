"""Sweeps: scenes × methods × parameter grids → one row per evaluation, in a pandas DataFrame.

Each scene's G-buffer is rendered once per instant its methods need and its reference once;
each evaluation runs the method, reduces the squared error and, if asked, the SSIM map against
the reference on the GPU (scalar readbacks), and computes FLIP, if asked, on the CPU. Rows are
appended to a CSV file as they are made, so an interrupted sweep keeps every finished row and
a rerun with the same file skips them. With a Dask cluster the same evaluations run on its
workers, a scene's configurations split into chunks (blurlab.cluster).
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
import statistics
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from . import metrics as m
from .accumulation import default_reference_samples
from .context import Context
from .methods import (
    blur_steps,
    check_param,
    check_steps,
    method,
    method_instant,
    methods,
    render_steps,
)
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


@dataclass(frozen=True)
class Settings:
    """What every evaluation of one sweep shares; small and picklable, so workers get it too."""

    size: tuple[int, int]
    shutter: tuple[float, float] | None
    reference_samples: int | None
    metrics: tuple[str, ...]
    repeats: int


def sweep(
    ctx: Context | None,
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
    cluster=None,
    chunk_size: int | None = None,
) -> pd.DataFrame:
    """Evaluates every method at every point of its grid on every scene.

    `methods_and_grids`: a list of method names (default grids), a {name: grid} mapping, or
    None for every single-frame method with its default grid; a post-process method's grid may
    also vary `steps` (bl.blur_steps). `reference_samples`: N of each
    scene's reference; None picks max(64, 2 × the longest motion in pixels), at most 1024.
    `out`: a CSV file that rows are appended to as they finish; rows already in it are
    skipped (a row cut short by a crash is dropped and evaluated again). Each pass time is the
    median of `repeats` runs, all configurations of a scene timed back to back before any error
    is computed (a GPU left idle while the CPU computes FLIP clocks down).

    `cluster`: run on Dask workers instead of `ctx` (then pass ctx=None): a
    ``distributed.Client``, a cluster such as ``bl.local_cluster()``, or a scheduler address
    ``"tcp://host:8786"``. Each worker renders on its own device and returns rows; they land
    in the same table and the same `out` file as a local sweep's (docs/distributed.md).
    `chunk_size`: at most this many configurations of one scene per task (default 8; chunks
    shrink towards the end of the sweep so that the workers finish together).
    """
    if cluster is None and not isinstance(ctx, Context):
        raise TypeError("blurlab.sweep needs a blurlab Context (or ctx=None and a cluster)")
    if cluster is not None and ctx is not None:
        raise ValueError(
            "blurlab.sweep: with cluster=, every worker renders on its own device; pass ctx=None"
        )
    if cluster is not None:
        from .cluster import check_cluster

        check_cluster(cluster)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 1:
        raise ValueError(f"blurlab.sweep: repeats must be an integer >= 1, not {repeats!r}")
    if chunk_size is not None and (
        isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1
    ):
        raise ValueError(
            f"blurlab.sweep: chunk_size must be None or an integer >= 1, not {chunk_size!r}"
        )
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
            if key != "steps" and key not in method(name).params:
                raise ValueError(f"blurlab.sweep: {name} has no parameter {key!r}")
        # Every value now, not an hour into the sweep when its turn comes.
        for point in grid_points(grid):
            for key, value in point.items():
                if key == "steps":  # n sub-intervals of the shutter (bl.blur_steps)
                    check_steps(name, value)
                else:
                    check_param(name, key, value)
    scene_list = [_scene(s) for s in scenes]
    if not scene_list:
        raise ValueError("blurlab.sweep: no scenes")
    path = Path(out) if out is not None else None
    if path is not None and path.suffix.lower() != ".csv":
        raise ValueError(f"blurlab.sweep: results go to a .csv file (appendable), not {path.name}")
    settings = Settings(
        (int(size[0]), int(size[1])),
        None if shutter is None else tuple(shutter),
        reference_samples,
        tuple(metrics),
        repeats,
    )
    done = _finished_keys(path)
    # Every evaluation asked for, in table order, and per scene those not yet in `out`.
    keys = []
    pending: list[list[tuple]] = [[] for _ in scene_list]
    for i, scene in enumerate(scene_list):
        for name, grid in methods_and_grids.items():
            backend = (backends or {}).get(name)
            for point in grid_points(grid):
                key = _key(scene.name, name, backend or method(name).backends[0], point, size)
                keys.append(key)
                if key not in done:
                    pending[i].append((name, point, backend, key))
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(keys), desc="sweep", unit="evaluation")
        bar.update(len(keys) - sum(len(jobs) for jobs in pending))

    def record(key: tuple, row: dict) -> None:
        if path is not None:
            _append(path, row)
        done[key] = row
        if bar:
            bar.update()

    try:
        if cluster is None:
            for scene, jobs in zip(scene_list, pending, strict=True):
                if jobs:
                    for key, row in evaluate_scene(ctx, scene, jobs, settings, {}):
                        record(key, row)
        elif any(pending):  # a finished sweep needs no cluster
            from .cluster import sweep_on_cluster

            sweep_on_cluster(cluster, scene_list, pending, settings, record, chunk_size, bar)
    finally:
        if bar:
            bar.close()
    return pd.DataFrame([done[key] for key in dict.fromkeys(keys) if key in done])


def evaluate_scene(
    ctx: Context, scene: Scene, jobs: Sequence[tuple], settings: Settings, cache: dict
) -> Iterator[tuple[tuple, dict]]:
    """Evaluates `jobs` = [(method, point, backend, key)] of one scene; yields (key, row) as
    each row is finished. `cache` holds the scene's frames and reference between calls (a
    worker keeps one per scene it has worked on)."""
    size = settings.size
    info = ctx.info()
    # Timing first, every configuration back to back: the GPU stays busy, so its clocks stay
    # up. Computing SSIM and FLIP between runs left it idle long enough to clock down, and
    # single runs after that were several times slower on the H100. Each method runs once
    # untimed first: it compiles (and, on llvmpipe, JITs), and the GPU wakes up.
    timings = {}
    warmed: set = set()
    for name, point, backend, key in jobs:
        frames, reference = _scene_inputs(ctx, scene, name, point, settings, cache)
        params = _without_steps(point)
        if (name, backend) not in warmed:
            blur_steps(ctx, frames, name, backend, **params)
            warmed.add((name, backend))
        runs = []
        for _ in range(settings.repeats):
            result = blur_steps(ctx, frames, name, backend, **params)
            runs.append({p: t.ms for p, t in result.timings.items()})
            clock = result.clock
            del result  # back to the pool before the next run
        timings[key] = (runs, clock)
    # Then the error of each configuration, one untimed run each.
    for name, point, backend, key in jobs:
        frames, reference = _scene_inputs(ctx, scene, name, point, settings, cache)
        runs, clock = timings[key]
        result = blur_steps(ctx, frames, name, backend, timed=False, **_without_steps(point))
        row = {
            "scene": scene.name,
            "method": name,
            "backend": result.backend,
            "params": json.dumps(point, sort_keys=True),
            **{f"param_{k}": v for k, v in point.items()},
            **{f"ms_{p}": statistics.median(r[p] for r in runs) for p in runs[0]},
            "total_ms": statistics.median(sum(r.values()) for r in runs),
            "repeats": settings.repeats,
            "clock": clock,
            "psnr": m.psnr_from_mse(m.gpu_mse(ctx, result.textures["color"], reference.texture)),
        }
        # PSNR and SSIM are reduced on the GPU (SPEC.md §6); only FLIP needs the images.
        if "ssim" in settings.metrics:
            row["ssim"] = m.gpu_ssim(ctx, reference.texture, result.textures["color"])
        if "flip" in settings.metrics:
            row["flip"] = m.flip(reference.color, result.color)
        row.update(
            {
                "device": info["device"],
                "renderer": info["renderer"],
                "width": size[0],
                "height": size[1],
                "reference_samples": reference.samples,
                "shutter": json.dumps([frames[0].shutter[0], frames[-1].shutter[1]]),
            }
        )
        del result  # its textures go back to the pool before the next evaluation
        yield key, row


def _without_steps(point: dict) -> dict:
    return {k: v for k, v in point.items() if k != "steps"}


def _scene_inputs(ctx, scene, name, point, settings: Settings, cache: dict):
    """The frames at the method's instant (one, or one per step of the shutter: `steps` in
    the point) and the scene's reference, each made once."""
    params = _without_steps(point)
    instant = method_instant(name, params)
    steps = point.get("steps", 1)
    frames = cache.setdefault("frames", {})
    if (instant, 1) not in frames:
        frames[(instant, 1)] = [ctx.render(scene, settings.size, settings.shutter, instant=instant)]
    if (instant, steps) not in frames:
        frames[(instant, steps)] = render_steps(
            ctx, scene, name, steps, settings.size, settings.shutter, **params
        )
    frame = frames[(instant, 1)][0]
    if "reference" not in cache:
        n = settings.reference_samples
        if n is None:
            n = default_reference_samples(frame)
        cache["reference"] = ctx.reference(
            scene,
            settings.size,
            check_shutter(scene.shutter if settings.shutter is None else settings.shutter),
            samples=n,
            progress=False,
        )
    return frames[(instant, steps)], cache["reference"]


def _key(scene: str, name: str, backend: str, point: dict, size) -> tuple:
    return (scene, name, backend, json.dumps(point, sort_keys=True), int(size[0]), int(size[1]))


def _finished_keys(path: Path | None) -> dict:
    if path is None or not path.exists() or path.stat().st_size == 0:
        return {}
    _drop_partial_line(path)
    table = pd.read_csv(path)
    done = {}
    for row in table.to_dict("records"):
        row = {k: v for k, v in row.items() if not (isinstance(v, float) and math.isnan(v))}
        if not {"scene", "method", "backend", "params", "width", "height"} <= set(row):
            continue  # not a finished row: evaluate it again
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


def _drop_partial_line(path: Path) -> None:
    """Cuts a last line that has no newline (a write cut short by a crash or a kill), so the
    next row starts on a line of its own and the cut row is evaluated again."""
    with path.open("rb+") as f:
        data = f.read()
        if data and not data.endswith(b"\n"):
            f.truncate(data.rfind(b"\n") + 1)


def _append(path: Path, row: dict) -> None:
    """Appends one row; a new column (a method with other passes) rewrites the file once.
    Each row is one write() of one whole line: an interrupt (KeyboardInterrupt arrives
    between Python operations) leaves finished rows only."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.exists() and path.stat().st_size > 0:
        _drop_partial_line(path)
        with path.open(newline="") as f:
            header = next(csv.reader(f))
        if set(row) <= set(header):
            line = io.StringIO()
            csv.DictWriter(line, header).writerow(row)
            with path.open("a", newline="") as f:
                f.write(line.getvalue())
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
