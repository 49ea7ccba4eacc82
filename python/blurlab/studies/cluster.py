"""Sweeps on a Dask cluster (dask.distributed): ``bl.sweep(None, ..., cluster=...)``.

Each worker is one process with one thread and owns one EGL device: the one ``BLURLAB_DEVICE``
names in its environment, else the GPU at its rank (a worker named ``3`` or ``host-3`` takes
the fourth GPU, wrapping around), else llvmpipe. A worker keeps the frames and references of
the scenes it has worked on. The client hands out chunks of one scene's configurations, keeping
each worker on its scene while that scene has work left, and writes rows to the sweep's table
and file as chunks return. A worker that helps on another's scene imports its references from
a worker that keeps them, so a scene's reference is rendered once.

``local_cluster()`` (blurlab.studies.cluster_devices) starts workers on this machine, listening
on its loopback only: one per GPU, or one per core with llvmpipe. Other machines' schedulers
are reached over TLS (``bl.scheduler``, blurlab.studies.scheduler); a plain tcp:// one on
another host gets a warning.
"""

from __future__ import annotations

import json
import logging
import math
import time
import uuid
from collections import OrderedDict, deque

from .._core import ContextLost
from ..core.context import Context
from . import identity
from .cluster_devices import worker_device
from .evaluation import SETUP_PHASES, WARM_UP, evaluate_scene
from .scheduler import CONNECT_TIMEOUT_S, Scheduler, require_distributed, scheduler

# Scenes whose frames and references a worker keeps; the client keeps each worker on one scene
# at a time, so two are enough for the hand-over between scenes.
SCENES_KEPT = 2
MAX_CHUNK = 8  # configurations per task unless bl.sweep's chunk_size says otherwise
# Chunks a worker has at once: the one it runs and the next, so that it starts the next as soon
# as it finishes one instead of idling while the client hears of it and hands out another (on
# one H100, a 4K sweep of 122 chunks idled 2.2 s with one and 0.5 s with two: docs/benchmarks.md).
CHUNKS_IN_FLIGHT = 2
# A worker's account (worker_report): evaluation's setup phases (a helper on another worker's
# scene pays them again unless it imports them) and warm-up runs, and the references it
# imported from another worker (uploads) or exported to one (downloads); the rest of its busy
# time is evaluations (timed runs and metrics).
ACCOUNT = (*SETUP_PHASES, WARM_UP, "imports", "exports")

_worker_state: dict = {}  # this process as a Dask worker: its Context and scene caches


def worker_context() -> Context:
    """This worker's Context, opened on its first task."""
    if "ctx" not in _worker_state:
        worker = require_distributed().get_worker()
        if worker.state.nthreads != 1:
            raise RuntimeError(
                f"blurlab: worker {worker.name} has {worker.state.nthreads} threads; a GL "
                "context belongs to one thread: start workers with --nthreads 1 "
                "(LocalCluster: threads_per_worker=1)"
            )
        start = time.perf_counter()
        _worker_state["ctx"] = Context(worker_device(worker.name))
        _worker_state["scenes"] = OrderedDict()
        opened = time.perf_counter() - start
        if "log" in _worker_state:  # a context opened again after a GPU reset
            _worker_state["log"]["context_s"] += opened
        else:
            _worker_state["log"] = _new_log(opened)
    return _worker_state["ctx"]


def _drop_lost_context(error: ContextLost) -> None:
    """Forgets this worker's context, which the GPU reset, and everything made on it (its
    scenes' frames and references): the next task opens a new one. Logged with the reset's
    status (whether this context's own work caused it)."""
    logging.getLogger("blurlab").warning("a new context after a GPU reset: %s", error)
    _worker_state.pop("ctx", None)
    _worker_state.pop("scenes", None)
    _worker_state["log"]["context_resets"] += 1


# Context's counters of troubles met and mended while evaluating (Context.fence_timeouts: waits
# the driver cut short; Context.stale_readbacks: batches of metrics scored again;
# Context.pacing_waits: waits at the bound on unfinished passes), which a worker's account and
# a sweep's table report by these names.
CONTEXT_COUNTERS = ("fence_timeouts", "stale_readbacks", "pacing_waits")
# And the worker's own: the contexts it opened again after the GPU reset one
# (blurlab.ContextLost), each time evaluating its chunk again from the start.
WORKER_COUNTERS = (*CONTEXT_COUNTERS, "context_resets")
# The times one chunk is evaluated again on a new context before the sweep gives up on it.
RESETS_PER_CHUNK = 2


def context_counts(ctx: Context) -> dict[str, int]:
    """The context's CONTEXT_COUNTERS now."""
    return {name: getattr(ctx, name)() for name in CONTEXT_COUNTERS}


def _new_log(context_s: float) -> dict:
    phases = {f"{phase}_s": 0.0 for phase in ACCOUNT}
    counts = {"tasks": 0, "evaluations": 0, "imports": 0, "exports": 0, "next_chunk_waiting": 0}
    counts.update(dict.fromkeys(WORKER_COUNTERS, 0))
    return {"context_s": context_s, **counts, "busy_s": 0.0, **phases}


def run_chunk(scene, scene_key, jobs, settings, imported=None) -> tuple[str, list, dict]:
    """On a worker: evaluates `jobs` of `scene`; returns (worker name, [(key, row)], costs),
    costs = {"seconds": the task's wall time, "setup_s": what it spent on the scene's
    references and G-buffers, "evaluations": len(jobs)}: the client's estimate of what a
    helper on this scene would pay before its first evaluation. `imported`: the scene's
    references from another worker (export_scene_inputs), used unless this worker has them.
    Where the GPU resets the worker's context meanwhile (blurlab.ContextLost), the chunk is
    evaluated again from the start on a new one, up to RESETS_PER_CHUNK times."""
    resets = 0
    while True:
        try:
            return _run_chunk_once(scene, scene_key, jobs, settings, imported)
        except ContextLost as error:
            _drop_lost_context(error)  # also when giving up: later chunks get a new context
            resets += 1
            if resets > RESETS_PER_CHUNK:
                raise


def _run_chunk_once(scene, scene_key, jobs, settings, imported) -> tuple[str, list, dict]:
    ctx = worker_context()  # its first call opens the context: counted apart, as context_s
    start = time.perf_counter()
    ctx.make_current()  # a no-op on the thread that made it, which is every task's thread
    log = _worker_state["log"]
    cache = _scene_cache(scene_key)
    if imported and "reference" not in cache:
        for key, value in imported.items():
            cache[key] = value.attached(ctx) if key.startswith("reference") else value
        log["imports"] += 1
        log["imports_s"] += time.perf_counter() - start
    before = dict(cache["clock"].seconds) if "clock" in cache else {}
    counts_before = context_counts(ctx)
    rows = list(evaluate_scene(ctx, scene, jobs, settings, cache))
    for name, count in context_counts(ctx).items():
        log[name] += count - counts_before[name]
    seconds = time.perf_counter() - start
    setup = 0.0
    for phase in (*SETUP_PHASES, WARM_UP):
        spent = cache["clock"].seconds.get(phase, 0.0) - before.get(phase, 0.0)
        log[f"{phase}_s"] += spent
        setup += spent if phase in SETUP_PHASES else 0.0
    log["tasks"] += 1
    log["next_chunk_waiting"] += int(chunks_waiting() > 0)
    log["evaluations"] += len(rows)
    log["busy_s"] += seconds
    costs = {"seconds": seconds, "setup_s": setup, "evaluations": len(rows)}
    return str(require_distributed().get_worker().name), rows, costs


# A task this worker has been given but not yet run (distributed's worker task states).
NOT_YET_RUN = ("waiting", "ready", "constrained", "fetch", "flight", "missing")


def chunks_waiting() -> int:
    """Chunks this worker has been given besides the one it runs (CHUNKS_IN_FLIGHT)."""
    from dask.utils import key_split

    # The task runs on a worker thread while the worker's event loop adds and drops tasks:
    # iterating the live dict raised "dictionary changed size during iteration" and failed a
    # 20-minute llvmpipe sweep. dict.copy() runs without releasing the GIL, so the loop cannot
    # change the dict during the copy.
    tasks = require_distributed().get_worker().state.tasks.copy().values()
    return sum(key_split(task.key) == "run_chunk" and task.state in NOT_YET_RUN for task in tasks)


def _scene_cache(scene_key) -> dict:
    """This worker's cache of a scene, made the most recent; the oldest beyond SCENES_KEPT go."""
    scenes = _worker_state["scenes"]
    cache = scenes.pop(scene_key, {})
    scenes[scene_key] = cache
    while len(scenes) > SCENES_KEPT:
        scenes.popitem(last=False)
    return cache


# What a helper imports of a scene's cache: its references and the sample count chosen.
EXPORTED = ("reference", "reference_aa", "default_samples")


def export_scene_inputs(scene_key) -> dict | None:
    """On a worker that holds a scene: its references as images in memory (Reference.detached)
    for a helper, which then renders neither; None if this worker no longer keeps the scene."""
    cache = _worker_state.get("scenes", {}).get(scene_key)
    if cache is None or "reference" not in cache:
        return None
    start = time.perf_counter()
    exported = {
        key: cache[key].detached() if key.startswith("reference") else cache[key]
        for key in EXPORTED
        if key in cache
    }
    seconds = time.perf_counter() - start
    log = _worker_state["log"]
    log["exports"] += 1
    log["exports_s"] += seconds
    log["busy_s"] += seconds
    return exported


def worker_report() -> dict:
    """This worker's account since it opened its context (run it with ``client.run``): its
    device, the tasks and evaluations it ran, and where its busy seconds went: opening the
    context, the scenes' references and G-buffers, each method's first run in a task
    (``warm_up_s``), references imported from and exported to other workers, and the rest
    (timed runs and metrics, ``evaluations_s``). Idle time is the sweep's wall time less
    ``context_s`` and ``busy_s``. ``next_chunk_waiting``: the chunks at whose end this worker
    already had its next one, which it then started without waiting for the client.
    ``fence_timeouts``: the waits for the GPU in its tasks that the driver ended early
    (Context.fence_timeouts), each waited again. ``stale_readbacks``: the batches of GPU
    metrics whose partial sums came back without their tickets (Context.stale_readbacks),
    each scored again. ``pacing_waits``: the times its context waited for the GPU at the
    bound on unfinished passes (Context.pacing_waits). ``context_resets``: the times the GPU
    reset its context (blurlab.ContextLost) and it opened a new one to evaluate the chunk
    again."""
    if "ctx" not in _worker_state:
        return {"device": None, **_new_log(0.0), "evaluations_s": 0.0, "scenes_kept": []}
    info = _worker_state["ctx"].info()
    log = dict(_worker_state["log"])
    log["evaluations_s"] = log["busy_s"] - sum(log[f"{p}_s"] for p in ACCOUNT)
    log["device"] = f"EGL device {info['device_index']}: {info['renderer']}"
    log["scenes_kept"] = sorted(index for _, index in _worker_state["scenes"])
    return log


def forget_scenes() -> None:
    """Drops the frames and references this worker keeps, so that the next sweep renders its
    scenes anew, and starts its account (worker_report) anew; its context, compiled programs
    and texture pool stay (run it with ``client.run``)."""
    _worker_state.get("scenes", {}).clear()
    if "log" in _worker_state:
        _worker_state["log"] = _new_log(0.0)


def worth_helping(left: int, seconds_each: float | None, setup_s: float | None) -> bool:
    """Whether a worker should render a scene's inputs again to take part of the `left`
    evaluations another worker is working through, while none can export them yet: only if
    that worker alone would need more than twice the scene's setup (its references and
    G-buffers). Without estimates it waits: the first chunk that returns brings them, and a
    worker whose references it can import."""
    if seconds_each is None or setup_s is None:
        return False
    return left * seconds_each > 2.0 * setup_s


def account_since(before: dict, after: dict) -> dict:
    """A worker's account (worker_report) between two reports: counts and seconds subtracted,
    the rest (device, scenes kept) as they are after."""
    return {
        key: value - before.get(key, 0)
        if isinstance(value, (int, float)) and not isinstance(value, bool)
        else value
        for key, value in after.items()
    }


def account_table(accounts: dict, wall_s: float) -> str:
    """Each worker's account of a sweep (``table.attrs["workers"]``) as a Markdown table:
    where its share of the `wall_s` seconds went, idle time included; and the wall time on
    no worker's account (client, scheduler, transfers)."""
    lines = [
        "| worker | device | tasks (next waiting) | evaluations | context s | references s "
        "| G-buffers s | warm-up runs s | imports (s) | exports (s) | evaluations s | idle s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, r in sorted(accounts.items()):
        idle = wall_s - r["context_s"] - r["busy_s"]
        lines.append(
            f"| {name} | {r['device']} | {r['tasks']} ({r['next_chunk_waiting']}) "
            f"| {r['evaluations']} "
            f"| {r['context_s']:.1f} | {r['references_s']:.1f} | {r['g_buffers_s']:.1f} "
            f"| {r['warm_up_s']:.1f} | {r['imports']} ({r['imports_s']:.1f}) "
            f"| {r['exports']} ({r['exports_s']:.1f}) | {r['evaluations_s']:.1f} | {idle:.1f} |"
        )
    busiest = max((r["context_s"] + r["busy_s"] for r in accounts.values()), default=0.0)
    lines.append(
        f"\nnot on any worker's account (client, scheduler, transfers): {wall_s - busiest:.1f} s"
    )
    return "\n".join(lines)


def _scene_copy(scene):
    return scene


def check_cluster(cluster) -> None:
    """Raises unless `cluster` is a Client, a cluster object, a bl.scheduler(...) or a
    scheduler address."""
    distributed = require_distributed()
    if not (
        isinstance(cluster, (distributed.Client, Scheduler, str))
        or hasattr(cluster, "scheduler_address")
    ):
        raise TypeError(
            "blurlab.sweep: cluster must be a distributed.Client, a cluster (e.g. "
            "bl.local_cluster()), a scheduler (bl.scheduler('tls://host:8786', tls_ca=..., "
            f"tls_cert=..., tls_key=...)) or a scheduler address, not {cluster!r}"
        )


def connect(cluster):
    """(client, whether this call made it) for a Client, a cluster, a bl.scheduler(...) or a
    scheduler address. An address is checked as bl.scheduler checks it: a tls:// one without
    the TLS files is refused with the message the command line gives, and a plain tcp:// one
    that is not on this machine gets warn_if_exposed's warning."""
    distributed = require_distributed()
    check_cluster(cluster)
    if isinstance(cluster, distributed.Client):
        return cluster, False
    if isinstance(cluster, str):
        cluster = scheduler(cluster)
    if isinstance(cluster, Scheduler):
        return cluster.connect(), True
    return distributed.Client(cluster, timeout=CONNECT_TIMEOUT_S), True


def _device_info() -> dict:
    """On a worker: the device part of a row's identity, from its context."""
    return identity.device_identity(worker_context())


def cluster_device(client) -> dict:
    """The device every worker renders on and the code it runs (identity.device_identity, a
    part of each row's identity), asked of each worker in a task (a GL context belongs to the
    task thread). Raises where the workers render on different kinds of device or run other
    code: their rows would differ by worker, and a resumed sweep could not say which rows it
    may keep."""
    client.wait_for_workers(1, timeout=120)
    futures = [
        client.submit(_device_info, workers=[w], allow_other_workers=False, pure=False)
        for w in client.nthreads()
    ]
    found = {json.dumps(d, sort_keys=True) for d in client.gather(futures)}
    if len(found) != 1:
        raise RuntimeError(
            "blurlab.sweep: the cluster's workers render on different devices or run "
            f"different code ({sorted(found)}); a sweep's rows must not depend on the worker. "
            "Run one sweep per kind of device (BLURLAB_DEVICE or separate clusters), every "
            "worker from the same installation"
        )
    return json.loads(found.pop())


def sweep_on_cluster(cluster, scenes, pending, settings, record, chunk_size, bar) -> dict:
    """The client's side: hands out chunks, calls ``record(key, row)`` as rows come back;
    returns each worker's account of this sweep, {worker name: worker_report() since its
    start}.

    Each worker has up to CHUNKS_IN_FLIGHT chunks at once. It gets the next chunk of the scene
    it works on; when that scene has no work left, a scene no worker has started (the one with
    most work), and only when none is left, part of a scene another worker is on. It then
    imports that scene's references from a worker that keeps them (the images travel through
    Dask) rather than rendering them again; while none can export them yet, it renders them
    itself only where worth_helping says that pays. Rows therefore depend only on the scene and
    configuration, never on the worker.
    """
    distributed = require_distributed()
    client, own = connect(cluster)
    futures: dict = {}
    try:
        client.wait_for_workers(1, timeout=120)
        accounts_before = client.run(worker_report)
        queues = {i: deque(jobs) for i, jobs in enumerate(pending) if jobs}
        workers = list(client.nthreads())
        largest = chunk_size or MAX_CHUNK
        token = uuid.uuid4().hex[:12]
        shipped: dict = {}
        owner: dict = {}
        started: set = set()
        counts: dict = {}
        held: dict = {}  # worker: the scenes whose inputs it keeps, oldest first
        setup_s: dict = {}  # scene: the most a chunk of it spent on references, G-buffers
        seconds_each: dict = {}  # scene: a chunk's other seconds per evaluation
        exports: dict = {}  # scene: the future of its exported inputs (export_scene_inputs)
        awaited: dict = {}  # (worker, scene): the export its chunks given so far wait for
        done = distributed.as_completed()

        def estimate(values: dict, i):
            """Scene i's figure, else the mean over the scenes measured so far, else None."""
            if i in values:
                return values[i]
            return sum(values.values()) / len(values) if values else None

        def holder(worker, i):
            """A live worker other than `worker` that keeps scene i's inputs, or None."""
            kept_by = (w for w, kept in held.items() if i in kept and w != worker and w in workers)
            return next(kept_by, None)

        def will_hold(worker, i) -> bool:
            """Whether `worker` keeps scene i's inputs, or will once a chunk of scene i that it
            has already been given runs (its chunks run in the order given)."""
            return i in held.get(worker, ()) or any(
                w == worker and scene_of[f] == i for f, w in futures.items()
            )

        def can_help(worker, i) -> bool:
            """Whether `worker` takes part of scene i: it keeps the scene, or nobody else is on
            it, or another worker can export its inputs, or rendering them again pays."""
            if will_hold(worker, i):
                return True
            covered = any(owner.get(w) == i for w in futures.values() if w != worker)
            if not covered or holder(worker, i) is not None:
                return True
            each, setup = estimate(seconds_each, i), estimate(setup_s, i)
            return worth_helping(len(queues[i]), each, setup)

        def next_scene(worker):
            mine = owner.get(worker)
            if mine is not None and queues.get(mine):
                return mine
            fresh = [i for i in queues if queues[i] and i not in started]
            left = fresh or [i for i in queues if queues[i] and can_help(worker, i)]
            return max(left, key=lambda i: len(queues[i])) if left else None

        def imports_for(worker, i):
            """The export of scene i's inputs for `worker`, if it lacks them and another has
            them: one export task a scene, run on its holder, whose result Dask moves. A chunk
            given while an earlier one still waits for that export waits for it too: without
            the export among its inputs it would be ready first, run first and render the
            scene itself."""
            if (worker, i) in awaited:
                return awaited[worker, i]
            if will_hold(worker, i):  # it keeps them, or a chunk it was given renders them
                return None
            if i not in exports:
                source = holder(worker, i)
                if source is None:
                    return None
                # Loosely bound: if the holder dies, the export runs elsewhere and returns
                # None, and the helper renders the scene itself instead of waiting for ever.
                exports[i] = client.submit(
                    export_scene_inputs,
                    (token, i),
                    workers=[source],
                    allow_other_workers=True,
                    pure=False,
                    priority=1,  # before the holder's next chunk: the helper waits for it
                )
            awaited[worker, i] = exports[i]
            return exports[i]

        def assign(worker) -> None:
            i = next_scene(worker)
            if i is None:
                return
            owner[worker] = i
            started.add(i)
            # Guided self-scheduling: chunks shrink as the work left does, so the workers
            # finish together; a chunk is at most `largest` configurations of one scene.
            left = sum(len(q) for q in queues.values())
            size = max(1, min(largest, len(queues[i]), math.ceil(left / (2 * len(workers)))))
            chunk = [queues[i].popleft() for _ in range(size)]
            if i not in shipped:
                # A task that returns the scene, not scattered data: if the worker holding it
                # dies, Dask computes it again from the task instead of losing it.
                shipped[i] = client.submit(_scene_copy, scenes[i], pure=False)
            future = client.submit(
                run_chunk,
                shipped[i],
                (token, i),
                chunk,
                settings,
                imports_for(worker, i),
                workers=[worker],
                allow_other_workers=True,  # if this worker dies, another takes the chunk
                pure=False,
            )
            futures[future] = worker
            scene_of[future] = i
            done.add(future)
            if not queues[i]:  # its exported images are freed once the chunks holding them end
                exports.pop(i, None)

        scene_of: dict = {}

        def fill(worker) -> None:
            """Gives `worker` chunks until it has CHUNKS_IN_FLIGHT or none is left for it."""
            for _ in range(CHUNKS_IN_FLIGHT - sum(w == worker for w in futures.values())):
                assign(worker)

        for _ in range(CHUNKS_IN_FLIGHT):  # a chunk each before any worker's second
            for worker in workers:
                assign(worker)
        for future in done:
            worker = futures.pop(future)
            i = scene_of.pop(future)
            name, rows, costs = future.result()  # a worker's exception is raised here
            for key, row in rows:
                record(key, row)
            kept = [j for j in held.get(worker, []) if j != i] + [i]
            held[worker] = kept[-SCENES_KEPT:]
            awaited.pop((worker, i), None)  # it holds the scene now
            if costs["setup_s"] > 0:  # this chunk rendered the scene's inputs
                setup_s[i] = max(setup_s.get(i, 0.0), costs["setup_s"])
            if costs["evaluations"]:
                seconds_each[i] = (costs["seconds"] - costs["setup_s"]) / costs["evaluations"]
            counts[name] = counts.get(name, 0) + len(rows)
            if bar:
                bar.set_postfix(rows_per_worker=",".join(f"{n}:{c}" for n, c in counts.items()))
            alive = workers = list(client.nthreads())
            # This worker again (or, if it is gone, any), and workers that joined meanwhile.
            for target in [worker] + alive if worker in alive else alive:
                fill(target)
        if any(queues.values()):
            raise RuntimeError(
                "blurlab.sweep: the cluster has no workers left; "
                f"{sum(len(q) for q in queues.values())} evaluations were not run"
            )
        # Keyed by the workers' names, as the progress bar's rows_per_worker are.
        names = {w: str(i.get("name", w)) for w, i in client.scheduler_info()["workers"].items()}
        return {
            names.get(worker, str(worker)): account_since(accounts_before.get(worker, {}), report)
            for worker, report in client.run(worker_report).items()
        }
    finally:
        for future in futures:
            future.cancel()
        if own:
            client.close()
