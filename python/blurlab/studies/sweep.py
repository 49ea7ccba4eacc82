"""Sweeps: scenes × methods × parameter grids → one row per evaluation, in a pandas DataFrame.

Each scene's G-buffer is rendered once per instant its methods need and its reference once;
each evaluation runs the method and computes the registered metrics asked for (blurlab.metrics):
those with a GPU reduction (squared error, SSIM, FLIP) on the GPU against the reference,
reading the sums of a batch of evaluations back at once (docs/spec.md §6.3), the others from
the images read back. Rows are appended to a CSV file as they are made, so an interrupted
sweep keeps every finished row and a rerun with the same file skips those whose identity
(blurlab.studies.identity) is its own. With a Dask cluster the same evaluations run on its
workers, a scene's configurations split into chunks (blurlab.studies.cluster).
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path

import pandas as pd

from ..core.context import Context
from ..core.render import check_shutter, check_size
from ..methods import check_param, check_steps, method, methods
from ..metrics import check_names
from ..scene import scenes as builtin_scenes
from ..scene.model import Scene
from ..sizes import DEFAULT_SIZE
from . import cluster as dask_cluster
from . import identity
from .evaluation import (
    REFERENCE_OPTIONS,
    Settings,
    evaluate_scene,
    reference_kinds,
    scene_metrics,
)


def default_grids() -> dict:
    """Every method a single-shutter sweep can evaluate, with the default grid it declares
    (blurlab study's grids: sensible ranges, small enough for llvmpipe)."""
    return {name: method(name).default_grid for name in sweep_methods()}


MAX_SIZE = 16384  # the largest GL_MAX_TEXTURE_SIZE of the devices blurlab meets


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
    return builtin_scenes.get(item) if isinstance(item, (str, os.PathLike)) else item


def sweep(
    ctx: Context | None,
    scenes: Iterable,
    methods_and_grids=None,
    size=DEFAULT_SIZE,
    shutter=None,
    reference_samples: int | None = None,
    metrics: Sequence[str] | None = None,
    out: str | Path | None = None,
    progress: bool = True,
    backends: Mapping[str, str] | None = None,
    repeats: int = 3,
    cluster=None,
    chunk_size: int | None = None,
    caches: dict | None = None,
    readback_batch: int = 16,
    on_scene: Callable[[Scene, dict], None] | None = None,
) -> pd.DataFrame:
    """Evaluates every method at every point of its grid on every scene.

    `methods_and_grids`: a list of method names (default grids), a {name: grid} mapping, or
    None for every single-frame method with its default grid; a post-process method's grid may
    also vary `steps` (bl.blur_steps). `reference_samples`: N of each
    scene's reference; None picks max(64, 2 × the longest motion in pixels), at most 1024.
    `metrics`: names of registered metrics (bl.metrics.registered()), checked before any work;
    None computes each scene's defaults (bl.metrics.default_names: the HDR ones on HDR scenes).
    `out`: a CSV file that rows are appended to as they finish; a row already in it with the
    same identity (blurlab.studies.identity: scene name and content, method, backend,
    parameters, size, shutter, reference, device, metrics, blurlab's version; the `identity`
    column) is returned instead of evaluated again. Rows of other configurations stay in the
    file beside this sweep's and are never returned by it; a row cut short by a crash is
    dropped and evaluated again (docs/reliability.md, "Resuming a sweep"). Each pass time is the
    median of `repeats` runs, all configurations of a scene timed back to back before any error
    is computed (a GPU left idle while the CPU computes FLIP clocks down). `repeats=0` scores
    without timing: no warm-up or timed runs, total_ms NaN and no ms_ columns; such rows are a
    configuration of their own in `out` (an untimed row never answers a timed sweep).

    `cluster`: run on Dask workers instead of `ctx` (then pass ctx=None): a
    ``distributed.Client``, a cluster such as ``bl.local_cluster()``, or a scheduler address
    ``"tcp://host:8786"``. Each worker renders on its own device and returns rows; they land
    in the same table and the same `out` file as a local sweep's (docs/distributed.md), and
    ``table.attrs["workers"]`` holds where each worker's time went in this sweep
    (cluster.worker_report; cluster.account_table prints it).
    ``table.attrs["fence_timeouts"]`` counts the waits for the GPU that the driver cut short and
    ``table.attrs["stale_readbacks"]`` the batches of GPU metrics refused for missing tickets
    and scored again (docs/spec.md §6.3); each row's ``stale_readbacks`` column counts the
    refused reads of its own metrics, and a results file keeps it.
    ``table.attrs["pacing_waits"]`` counts the waits at the context's bound on unfinished
    passes (Context.pacing_waits).
    ``table.attrs["context_resets"]`` counts the chunks a cluster's workers evaluated again on
    a new context after the GPU reset theirs (blurlab.ContextLost); a local sweep whose context
    the GPU resets raises ContextLost, and a new context resumes from `out`.
    ``table.attrs["resumed"]`` counts the rows this call took from `out` instead of evaluating
    them.
    `chunk_size`: at most this many configurations of one scene per task (default 8; chunks
    shrink towards the end of the sweep so that the workers finish together).
    `caches`: a dict that a local sweep fills, per scene name, with what it rendered (frames
    by instant, "reference", "reference_aa") and the seconds it spent rendering them
    ("clock", a PhaseClock with "references" and "g_buffers"), for a caller that shows the
    same images (blurlab study); a scene's "keep_colours", set before, names the (method,
    params JSON) whose output colours it keeps ("colours"). On a cluster it stays as it was.
    `readback_batch`: the GPU metrics of up to this many evaluations of a scene are read back
    together, after one wait (metrics.MetricQueue), so the GPU runs one evaluation while the
    CPU issues the next; 1 waits for each evaluation's scalars. The values are the same bits
    either way; rows reach `out` a batch at a time.
    `on_scene(scene, cache)`: called on this thread once a local sweep has evaluated a scene,
    with its cache (as `caches` holds it), for work that can start then while the GPU goes on
    with the next scene (the study's pictures); not called for a scene with nothing left to
    evaluate, nor on a cluster.
    """
    if cluster is None and not isinstance(ctx, Context):
        raise TypeError("blurlab.sweep needs a blurlab Context (or ctx=None and a cluster)")
    if cluster is not None and ctx is not None:
        raise ValueError(
            "blurlab.sweep: with cluster=, every worker renders on its own device; pass ctx=None"
        )
    if cluster is not None:
        dask_cluster.check_cluster(cluster)
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < 0:
        raise ValueError(
            f"blurlab.sweep: repeats must be an integer >= 1, or 0 to score without timing, "
            f"not {repeats!r}"
        )
    if (
        isinstance(readback_batch, bool)
        or not isinstance(readback_batch, int)
        or readback_batch < 1
    ):
        raise ValueError(
            f"blurlab.sweep: readback_batch must be an integer >= 1, not {readback_batch!r}"
        )
    if chunk_size is not None and (
        isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1
    ):
        raise ValueError(
            f"blurlab.sweep: chunk_size must be None or an integer >= 1, not {chunk_size!r}"
        )
    # The size now, not when the first scene renders (a cluster's workers check their own
    # device's limit again).
    size = check_size(size, ctx.max_texture_size if ctx is not None else MAX_SIZE)
    if metrics is not None:
        metrics = check_names(metrics, "blurlab.sweep")
    if methods_and_grids is None:
        methods_and_grids = sweep_methods()
    if not isinstance(methods_and_grids, Mapping):
        methods_and_grids = {name: method(name).default_grid for name in methods_and_grids}
    for name, grid in methods_and_grids.items():
        if not method(name).sweepable:  # method() raises for unknown names
            raise ValueError(f"blurlab.sweep: {name} needs a frame sequence; it is not swept")
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
        metrics,
        repeats,
        readback_batch,
    )
    client, own_client = (None, False)
    if cluster is not None:
        client, own_client = dask_cluster.connect(cluster)
    try:
        device = (
            dask_cluster.cluster_device(client)
            if client is not None
            else identity.device_identity(ctx)
        )
        plan = _plan(scene_list, methods_and_grids, backends, settings, device, path)
    except BaseException:
        if own_client:
            client.close()
        raise
    keys, columns, pending, done = plan
    # rows this call takes from `out` rather than evaluating (a resumed sweep)
    resumed = len(keys) - sum(len(jobs) for jobs in pending)
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(keys), desc="sweep", unit="evaluation")
        bar.update(resumed)

    rows_file = _RowFile(path) if path is not None else None

    def record(key: str, row: dict) -> None:
        row.update(columns[key])
        if rows_file is not None:
            rows_file.append(row)
        done[key] = row
        if bar:
            bar.update()

    accounts = None
    counts_before = dask_cluster.context_counts(ctx) if ctx is not None else None
    try:
        if cluster is None:
            for scene, jobs in zip(scene_list, pending, strict=True):
                cache = {} if caches is None else caches.setdefault(scene.name, {})
                if jobs:
                    for key, row in evaluate_scene(ctx, scene, jobs, settings, cache):
                        record(key, row)
                    if on_scene is not None:
                        on_scene(scene, cache)
        elif any(pending):
            accounts = dask_cluster.sweep_on_cluster(
                client, scene_list, pending, settings, record, chunk_size, bar
            )
    finally:
        if own_client:
            client.close()
        if bar:
            bar.close()
        if rows_file is not None:
            rows_file.close()
    table = pd.DataFrame([done[key] for key in dict.fromkeys(keys) if key in done])
    if accounts is not None:  # where each worker's time went (cluster.worker_report)
        table.attrs["workers"] = accounts
    table.attrs["resumed"] = resumed
    # The context's counters over this sweep: summed over the workers' accounts on a cluster.
    counters = dask_cluster.WORKER_COUNTERS
    if accounts is not None:
        table.attrs.update({n: sum(a[n] for a in accounts.values()) for n in counters})
    elif ctx is not None:  # a lost context raised ContextLost here: no resets to count
        after = dask_cluster.context_counts(ctx)
        table.attrs.update({n: after[n] - counts_before[n] for n in dask_cluster.CONTEXT_COUNTERS})
        table.attrs["context_resets"] = 0
    else:  # a cluster's sweep that had nothing left to evaluate
        table.attrs.update(dict.fromkeys(counters, 0))
    return table


def _plan(scene_list, methods_and_grids, backends, settings: Settings, device: dict, path):
    """(keys, columns, pending, done): every evaluation asked for, in table order, by its
    identity; {identity: the columns that spell it out}; per scene, the jobs whose identity
    no row of `path` has; and {identity: row} of the rows `path` holds."""
    done = _finished_rows(path)
    keys = []
    columns: dict[str, dict] = {}
    pending: list[list[tuple]] = [[] for _ in scene_list]
    for i, scene in enumerate(scene_list):
        shared = scene_identity(scene, settings, device)
        for name, grid in methods_and_grids.items():
            backend = (backends or {}).get(name)
            for point in grid_points(grid):
                parts = {
                    **shared,
                    "method": name,
                    "backend": backend or method(name).backends[0],
                    "params": json.dumps(point, sort_keys=True),
                }
                key = identity.row_identity(parts)
                keys.append(key)
                columns[key] = _identity_columns(key, shared)
                if key not in done:
                    pending[i].append((name, point, backend, key))
    return keys, columns, pending, done


def scene_identity(scene: Scene, settings: Settings, device: dict) -> dict:
    """What every row of `scene` in a sweep shares of its identity (blurlab.studies.identity):
    the scene's name and content, size, shutter, reference, metric set, device, blurlab's
    version and, for an untimed sweep, that it is untimed; a row adds its method, backend and
    parameters."""
    wanted = settings.metrics if settings.metrics is not None else scene_metrics(scene)
    shutter = check_shutter(scene.shutter if settings.shutter is None else settings.shutter)
    return {
        "scene": scene.name,
        identity.SCENE_DIGEST: identity.scene_digest(scene),
        "width": settings.size[0],
        "height": settings.size[1],
        "shutter": [float(shutter[0]), float(shutter[1])],
        identity.REFERENCE: {
            "samples": "auto" if settings.reference_samples is None else settings.reference_samples,
            # which of the temporal and the antialiased reference (docs/spec.md §11) it needs
            "kinds": reference_kinds(wanted),
            **REFERENCE_OPTIONS,
        },
        identity.METRIC_SET: list(wanted),
        **device,
        identity.VERSION: identity.version(),
        # only where it is so, so timed rows keep the identities they always had
        **({"timed": False} if settings.repeats == 0 else {}),
    }


def _identity_columns(key: str, shared: dict) -> dict:
    """The columns a row gets beside evaluation's: its identity hash and the components that
    no other column spells out already (the reference's definition, the metric set, the
    scene's digest, blurlab's version)."""
    return {
        identity.IDENTITY: key,
        identity.SCENE_DIGEST: shared[identity.SCENE_DIGEST],
        identity.REFERENCE: json.dumps(shared[identity.REFERENCE], sort_keys=True),
        identity.METRIC_SET: json.dumps(shared[identity.METRIC_SET]),
        identity.VERSION: shared[identity.VERSION],
        identity.CODE: shared[identity.CODE],
    }


def _finished_rows(path: Path | None) -> dict:
    """{identity: row} of the finished rows in `path`. Rows of other configurations stay in
    the file but are never returned for this one; rows without an identity (files written
    before rows had one) are evaluated again."""
    if path is None or not path.exists() or path.stat().st_size == 0:
        return {}
    drop_partial_line(path)
    text = {
        c: str for c in (identity.IDENTITY, identity.SCENE_DIGEST, identity.VERSION, identity.CODE)
    }
    table = read_row_file(path, dtype=text)
    if identity.IDENTITY not in table:
        return {}
    done = {}
    for row in table.to_dict("records"):
        row = {k: v for k, v in row.items() if not (isinstance(v, float) and math.isnan(v))}
        if isinstance(row.get(identity.IDENTITY), str):
            done[row[identity.IDENTITY]] = row
    return done


def read_row_file(path: Path, **options) -> pd.DataFrame:
    """A sweep's CSV file as a table, every number the one written. pandas before 3.1 reads
    floats with a fast parser that is not correctly rounded by default: a 17-digit PSNR can
    come back one unit in the last place off, so a finished row read back would differ from
    the same row evaluated again (3.1 made the exact parser the default and deprecated the
    option)."""
    if tuple(int(part) for part in pd.__version__.split(".")[:2]) < (3, 1):
        options.setdefault("float_precision", "round_trip")
    return pd.read_csv(path, **options)


def drop_partial_line(path: Path) -> None:
    """Cuts a last line that has no newline (a write cut short by a crash or a kill), so the
    next row starts on a line of its own and the cut row is evaluated again."""
    with path.open("rb+") as f:
        data = f.read()
        if data and not data.endswith(b"\n"):
            f.truncate(data.rfind(b"\n") + 1)


class _RowFile:
    """The sweep's CSV file: rows appended as they finish, each one write() of one whole line
    (an interrupt, which arrives between Python operations, leaves finished rows only). The
    header is read once per sweep and the file stays open for appending (reading the file
    again for each row cost 0.3 to 0.6 ms a row on a 2-core machine, at 100 to 5000 rows:
    more than an evaluation's GPU time at 1080p); a row with a new column (a method with other
    passes) rewrites the file once."""

    def __init__(self, path: Path):
        self.path = path
        self.header: list[str] | None = None  # None: not read yet, or no file
        self.columns: set[str] = set()
        self.file = None  # open for appending while the header is known

    def append(self, row: dict) -> None:
        if self.header is None and self.path.exists() and self.path.stat().st_size > 0:
            drop_partial_line(self.path)
            with self.path.open(newline="") as f:
                self._known(next(csv.reader(f)))
        if self.header is None or not self.columns.issuperset(row):
            self._rewrite(row)
            return
        line = io.StringIO()
        csv.DictWriter(line, self.header).writerow(row)
        if self.file is None:
            self.file = self.path.open("ab", buffering=0)
        self.file.write(line.getvalue().encode())

    def close(self) -> None:
        if self.file is not None:
            self.file.close()
            self.file = None

    def _known(self, header: list[str]) -> None:
        self.header, self.columns = header, set(header)

    def _rewrite(self, row: dict) -> None:
        """The file anew with `row` last: a new file, or one whose header lacks a column."""
        self.close()
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if self.header is None:
            with self.path.open("w", newline="") as f:
                writer = csv.DictWriter(f, list(row))
                writer.writeheader()
                writer.writerow(row)
            self._known(list(row))
            return
        # the rows already written are copied as text, never parsed and formatted again,
        # so their numbers keep every bit
        with self.path.open(newline="") as f:
            old = list(csv.DictReader(f))
        header = self.header + [c for c in row if c not in self.columns]
        tmp = self.path.with_suffix(".csv.tmp")
        with tmp.open("w", newline="") as f:
            writer = csv.DictWriter(f, header)
            writer.writeheader()
            writer.writerows(old)
            writer.writerow(row)
        tmp.replace(self.path)
        self._known(header)


def sweep_methods() -> list[str]:
    """Registered methods that a single-shutter sweep can evaluate."""
    return [n for n in methods() if method(n).sweepable]
