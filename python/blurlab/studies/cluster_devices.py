"""Where a sweep's Dask workers run: the device each worker renders on (``BLURLAB_DEVICE``, else
the GPU at its rank, else llvmpipe), and ``local_cluster()``, which starts workers on this
machine. blurlab.studies.cluster runs the sweep on them."""

from __future__ import annotations

import os
import re

from ..core.context import Context
from ..core.gl import DEVICE_MODES
from .scheduler import is_loopback, require_distributed


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


def gpu_share(text: str, available: int) -> int:
    """BLURLAB_GPUS: how many of the `available` GPUs the workers' ranks wrap over ('' or
    '0': all of them)."""
    text = text.strip()
    if not text:
        return available
    if not text.isdigit():
        raise ValueError(
            f"blurlab: BLURLAB_GPUS must be a GPU count (0: all {available}), not {text!r}"
        )
    count = int(text)
    return available if count == 0 else min(count, available)


def worker_device(name=None, environ=None) -> str | int:
    """The device a worker renders on: BLURLAB_DEVICE if set, else the GPU at the worker's
    rank modulo the GPU count (the first BLURLAB_GPUS GPUs where that is set), else
    "software"; "auto" when there are GPUs but no rank."""
    environ = os.environ if environ is None else environ
    text = environ.get("BLURLAB_DEVICE", "")
    if text.strip():
        return parse_device(text)
    gpus = [d["index"] for d in Context.devices() if d["kind"] == "gpu"]
    if not gpus:
        return "software"
    gpus = gpus[: gpu_share(environ.get("BLURLAB_GPUS", ""), len(gpus))]
    rank = worker_rank(name)
    return "auto" if rank is None else gpus[rank % len(gpus)]


def local_cluster(
    n_workers: int | None = None, device: str = "auto", gpus: int | None = None, **cluster_kwargs
):
    """A ``distributed.LocalCluster`` of blurlab workers: processes, one thread each.

    ``device="auto"``: one worker per GPU (worker i on GPU i) where EGL lists GPUs, else
    ``n_workers`` llvmpipe workers (default one per core), each given an equal share of the
    cores (``LP_NUM_THREADS``). ``"gpu"`` fails without a GPU; ``"software"`` always uses
    llvmpipe. `gpus` keeps the workers on the first that many GPUs (worker i on GPU i modulo
    `gpus`; None: all of them). Other keyword arguments go to ``LocalCluster`` (e.g.
    ``memory_limit``). Close it when done (``with bl.local_cluster() as cluster: ...``).
    """
    distributed = require_distributed()
    if device not in DEVICE_MODES:
        raise ValueError(
            f"blurlab.local_cluster: device must be one of {DEVICE_MODES}, not {device!r}"
        )
    if gpus is not None and (isinstance(gpus, bool) or not isinstance(gpus, int) or gpus < 1):
        raise ValueError(
            f"blurlab.local_cluster: gpus must be None or an integer >= 1, not {gpus!r}"
        )
    listed = [d for d in Context.devices() if d["kind"] == "gpu"]
    if device == "gpu" and not listed:
        raise RuntimeError(
            "blurlab.local_cluster: device='gpu' was asked for, but EGL lists no GPU; "
            "use device='auto' or 'software'"
        )
    on_gpus = bool(listed) and device != "software"
    used = len(listed) if gpus is None else min(gpus, len(listed))
    cores = len(os.sched_getaffinity(0))
    if n_workers is None:
        n_workers = used if on_gpus else cores
    if isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1:
        raise ValueError(
            f"blurlab.local_cluster: n_workers must be None or an integer >= 1, not {n_workers!r}"
        )
    # An empty BLURLAB_DEVICE (one set in this shell would pin every worker to one device)
    # leaves the choice to the worker's rank, over the first BLURLAB_GPUS GPUs.
    env = {"BLURLAB_DEVICE": "" if on_gpus else "software", "BLURLAB_GPUS": str(used)}
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
    # Its scheduler and workers listen on this machine's loopback only: Dask runs the code its
    # clients send, so an open port would let anyone on the network run code here.
    options.setdefault("host", "127.0.0.1")
    if not is_loopback(str(options["host"])):
        raise ValueError(
            "blurlab.local_cluster listens on this machine's loopback only, not on "
            f"host={options['host']!r}; for workers on other machines start a TLS scheduler "
            "(docs/distributed.md, 'Securing a cluster')"
        )
    if options["threads_per_worker"] != 1 or not options["processes"]:
        raise ValueError(
            "blurlab.local_cluster: workers must be processes with one thread each "
            "(a GL context belongs to one thread)"
        )
    # The sweep's client places every task itself; Dask's work stealing could only move an
    # export of a scene's references away from the worker that keeps them, making it useless.
    import dask  # installed with distributed

    with dask.config.set({"distributed.scheduler.work-stealing": False}):
        return distributed.LocalCluster(**options)
