"""Sweeps on a Dask cluster (dask.distributed): ``bl.sweep(None, ..., cluster=...)``.

Each worker is one process with one thread and owns one EGL device: the one ``BLURLAB_DEVICE``
names in its environment, else the GPU at its rank (a worker named ``3`` or ``host-3`` takes
the fourth GPU, wrapping around), else llvmpipe. A worker keeps the frames and references of
the scenes it has worked on, so a scene's reference is rendered once per worker that evaluates
it. The client hands out chunks of one scene's configurations, keeping each worker on its scene
while that scene has work left, and writes rows to the sweep's table and file as chunks return.

``local_cluster()`` starts workers on this machine: one per GPU, or one per core with llvmpipe.
"""

from __future__ import annotations

import math
import os
import re
import time
import uuid
from collections import OrderedDict, deque

from ..context import DEVICE_MODES, Context
from .evaluation import evaluate_scene

INSTALL_HINT = "pip install 'blurlab[distributed]' (or dask[distributed])"
# Scenes whose frames and references a worker keeps; the client keeps each worker on one scene
# at a time, so two are enough for the hand-over between scenes.
SCENES_KEPT = 2
MAX_CHUNK = 8  # configurations per task unless bl.sweep's chunk_size says otherwise
# The phases of a scene cache's PhaseClock (studies/evaluation.py) that a scene costs once per
# worker before its first evaluation: a helper on another worker's scene pays them again.
SETUP_PHASES = ("references", "g_buffers")
# Each method's first, untimed run in a task: its compiles and the first use of new textures.
WARM_UP_PHASE = "warm_up"

_worker_state: dict = {}  # this process as a Dask worker: its Context and scene caches


def _distributed():
    try:
        import distributed
    except ImportError:
        raise ImportError(f"blurlab: sweeps on a cluster need Dask: {INSTALL_HINT}") from None
    return distributed


def parse_device(text: str, what: str = "BLURLAB_DEVICE") -> str | int:
    """'gpu' -> 'gpu', '1' -> 1; raises naming `what` and the allowed values."""
    text = text.strip()
    if text.isdigit():
        return int(text)
    if text not in DEVICE_MODES:
        raise ValueError(
            f"blurlab: {what} must be one of {DEVICE_MODES} or an EGL device index, not {text!r}"
        )
    return text


def worker_rank(name) -> int | None:
    """A worker's rank from its name: 3 (LocalCluster) or 'host-3' (dask worker --nworkers)."""
    if isinstance(name, int) and not isinstance(name, bool):
        return name
    match = re.fullmatch(r"(?:.*-)?(\d+)", str(name)) if name is not None else None
    return int(match.group(1)) if match else None


def worker_device(name=None, environ=None) -> str | int:
    """The device a worker renders on: BLURLAB_DEVICE if set, else the GPU at the worker's
    rank (modulo the GPU count), else "software"; "auto" when there are GPUs but no rank."""
    environ = os.environ if environ is None else environ
    text = environ.get("BLURLAB_DEVICE", "")
    if text.strip():
        return parse_device(text)
    gpus = [d["index"] for d in Context.devices() if d["kind"] == "gpu"]
    if not gpus:
        return "software"
    rank = worker_rank(name)
    return "auto" if rank is None else gpus[rank % len(gpus)]


def local_cluster(n_workers: int | None = None, device: str = "auto", **cluster_kwargs):
    """A ``distributed.LocalCluster`` of blurlab workers: processes, one thread each.

    ``device="auto"``: one worker per GPU (worker i on GPU i) where EGL lists GPUs, else
    ``n_workers`` llvmpipe workers (default one per core), each given an equal share of the
    cores (``LP_NUM_THREADS``). ``"gpu"`` fails without a GPU; ``"software"`` always uses
    llvmpipe. Other keyword arguments go to ``LocalCluster`` (e.g. ``memory_limit``). Close it
    when done (``with bl.local_cluster() as cluster: ...``).
    """
    distributed = _distributed()
    if device not in DEVICE_MODES:
        raise ValueError(
            f"blurlab.local_cluster: device must be one of {DEVICE_MODES}, not {device!r}"
        )
    gpus = [d for d in Context.devices() if d["kind"] == "gpu"]
    if device == "gpu" and not gpus:
        raise RuntimeError(
            "blurlab.local_cluster: device='gpu' was asked for, but EGL lists no GPU; "
            "use device='auto' or 'software'"
        )
    on_gpus = bool(gpus) and device != "software"
    cores = len(os.sched_getaffinity(0))
    if n_workers is None:
        n_workers = len(gpus) if on_gpus else cores
    if isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1:
        raise ValueError(
            f"blurlab.local_cluster: n_workers must be None or an integer >= 1, not {n_workers!r}"
        )
    # An empty BLURLAB_DEVICE (one set in this shell would pin every worker to one device)
    # leaves the choice to the worker's rank.
    env = {"BLURLAB_DEVICE": "" if on_gpus else "software"}
    if not on_gpus and "LP_NUM_THREADS" not in os.environ:
        env["LP_NUM_THREADS"] = str(max(1, cores // n_workers))
    options = {
        "n_workers": n_workers,
        "threads_per_worker": 1,
        "processes": True,
        "dashboard_address": None,
        "env": env,
    }
    options.update(cluster_kwargs)
    if options["threads_per_worker"] != 1 or not options["processes"]:
        raise ValueError(
            "blurlab.local_cluster: workers must be processes with one thread each "
            "(a GL context belongs to one thread)"
        )
    return distributed.LocalCluster(**options)


def worker_context() -> Context:
    """This worker's Context, opened on its first task."""
    if "ctx" not in _worker_state:
        worker = _distributed().get_worker()
        if worker.state.nthreads != 1:
            raise RuntimeError(
                f"blurlab: worker {worker.name} has {worker.state.nthreads} threads; a GL "
                "context belongs to one thread: start workers with --nthreads 1 "
                "(LocalCluster: threads_per_worker=1)"
            )
        start = time.perf_counter()
        _worker_state["ctx"] = Context(worker_device(worker.name))
        _worker_state["scenes"] = OrderedDict()
        _worker_state["log"] = _new_log(time.perf_counter() - start)
    return _worker_state["ctx"]


def _new_log(context_s: float) -> dict:
    phases = {f"{phase}_s": 0.0 for phase in (*SETUP_PHASES, WARM_UP_PHASE)}
    return {"context_s": context_s, "tasks": 0, "evaluations": 0, "busy_s": 0.0, **phases}


def run_chunk(scene, scene_key, jobs, settings) -> tuple[str, list, dict]:
    """On a worker: evaluates `jobs` of `scene`; returns (worker name, [(key, row)], costs),
    costs = {"seconds": the task's wall time, "setup_s": what it spent on the scene's
    references and G-buffers, "evaluations": len(jobs)}: the client's estimate of what a
    helper on this scene would pay before its first evaluation."""
    ctx = worker_context()  # its first call opens the context: counted apart, as context_s
    start = time.perf_counter()
    ctx.make_current()  # a no-op on the thread that made it, which is every task's thread
    scenes = _worker_state["scenes"]
    cache = scenes.pop(scene_key, {})
    scenes[scene_key] = cache
    while len(scenes) > SCENES_KEPT:
        scenes.popitem(last=False)
    before = dict(cache["clock"].seconds) if "clock" in cache else {}
    rows = list(evaluate_scene(ctx, scene, jobs, settings, cache))
    seconds = time.perf_counter() - start
    log = _worker_state["log"]
    setup = 0.0
    for phase in (*SETUP_PHASES, WARM_UP_PHASE):
        spent = cache["clock"].seconds.get(phase, 0.0) - before.get(phase, 0.0)
        log[f"{phase}_s"] += spent
        setup += spent if phase in SETUP_PHASES else 0.0
    log["tasks"] += 1
    log["evaluations"] += len(rows)
    log["busy_s"] += seconds
    costs = {"seconds": seconds, "setup_s": setup, "evaluations": len(rows)}
    return str(_distributed().get_worker().name), rows, costs


def worker_report() -> dict:
    """This worker's account since it opened its context (run it with ``client.run``): its
    device, the tasks and evaluations it ran, and where its busy seconds went: opening the
    context, the scenes' references and G-buffers, each method's first run in a task
    (``warm_up_s``), and the rest (timed runs and metrics, ``evaluations_s``). Idle time is
    the sweep's wall time less ``context_s`` and ``busy_s``."""
    if "ctx" not in _worker_state:
        return {"device": None, **_new_log(0.0), "evaluations_s": 0.0, "scenes_kept": []}
    info = _worker_state["ctx"].info()
    log = dict(_worker_state["log"])
    spent = sum(log[f"{p}_s"] for p in (*SETUP_PHASES, WARM_UP_PHASE))
    log["evaluations_s"] = log["busy_s"] - spent
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
    """Whether a worker that holds none of a scene should take part of the `left` evaluations
    another worker is working through: only if that worker alone would need more than twice
    the scene's setup (its references and G-buffers, which the helper must render again).
    Without estimates yet it helps."""
    if seconds_each is None or setup_s is None:
        return True
    return left * seconds_each > 2.0 * setup_s


def _scene_copy(scene):
    return scene


def check_cluster(cluster) -> None:
    """Raises unless `cluster` is a Client, a cluster object or a scheduler address."""
    distributed = _distributed()
    if not (
        isinstance(cluster, (distributed.Client, str)) or hasattr(cluster, "scheduler_address")
    ):
        raise TypeError(
            "blurlab.sweep: cluster must be a distributed.Client, a cluster (e.g. "
            f"bl.local_cluster()) or a scheduler address 'tcp://host:8786', not {cluster!r}"
        )


def _connect(cluster):
    """(client, whether this call made it) for a Client, a cluster or a scheduler address."""
    distributed = _distributed()
    check_cluster(cluster)
    if isinstance(cluster, distributed.Client):
        return cluster, False
    return distributed.Client(cluster, timeout="60s"), True


def sweep_on_cluster(cluster, scenes, pending, settings, record, chunk_size, bar) -> None:
    """The client's side: hands out chunks, calls ``record(key, row)`` as rows come back.

    A worker that finishes a chunk gets the next chunk of the scene it works on; when that
    scene has no work left, a scene no worker has started (the one with most work), and only
    when none is left, part of a scene another worker is on (it then renders that reference
    too). Rows therefore depend only on the scene and configuration, never on the worker.
    """
    distributed = _distributed()
    client, own = _connect(cluster)
    futures: dict = {}
    try:
        client.wait_for_workers(1, timeout=120)
        queues = {i: deque(jobs) for i, jobs in enumerate(pending) if jobs}
        workers = list(client.nthreads())
        largest = chunk_size or MAX_CHUNK
        token = uuid.uuid4().hex[:12]
        shipped: dict = {}
        owner: dict = {}
        started: set = set()
        counts: dict = {}
        held: dict = {}  # worker: the scenes whose inputs it keeps, oldest first
        setup_s: dict = {}  # scene: what its first chunk on a worker spent on references
        seconds_each: dict = {}  # scene: a chunk's other seconds per evaluation
        done = distributed.as_completed()

        def worth_it(worker, i) -> bool:
            """Helping on scene i pays, or nobody else is working on it."""
            if i in held.get(worker, ()):
                return True
            covered = any(owner.get(w) == i for w in futures.values() if w != worker)
            return not covered or worth_helping(len(queues[i]), seconds_each.get(i), setup_s.get(i))

        def next_scene(worker):
            mine = owner.get(worker)
            if mine is not None and queues.get(mine):
                return mine
            fresh = [i for i in queues if queues[i] and i not in started]
            left = fresh or [i for i in queues if queues[i] and worth_it(worker, i)]
            return max(left, key=lambda i: len(queues[i])) if left else None

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
                workers=[worker],
                allow_other_workers=True,  # if this worker dies, another takes the chunk
                pure=False,
            )
            futures[future] = worker
            scene_of[future] = i
            done.add(future)

        scene_of: dict = {}
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
            if costs["setup_s"] > 0:  # this chunk rendered the scene's inputs
                setup_s[i] = max(setup_s.get(i, 0.0), costs["setup_s"])
            if costs["evaluations"]:
                seconds_each[i] = (costs["seconds"] - costs["setup_s"]) / costs["evaluations"]
            counts[name] = counts.get(name, 0) + len(rows)
            if bar:
                bar.set_postfix(rows_per_worker=",".join(f"{n}:{c}" for n, c in counts.items()))
            alive = workers = list(client.nthreads())
            busy = set(futures.values())
            # This worker again (or, if it is gone, any), and workers that joined meanwhile.
            for target in [worker if worker in alive else None] + alive:
                if target is not None and target not in busy:
                    assign(target)
                    busy.add(target)
        if any(queues.values()):
            raise RuntimeError(
                "blurlab.sweep: the cluster has no workers left; "
                f"{sum(len(q) for q in queues.values())} evaluations were not run"
            )
    finally:
        for future in futures:
            future.cancel()
        if own:
            client.close()
