"""What a driver does with a deep queue (docs/spec.md §6.3): untimed calls of a slow method
(by default the one drawn by fragment passes alone) issued without a wait for a while, then a
timer read, in a process of its own for each setting of the context's bound on unfinished
passes and its reset notification.
The H100's driver reset contexts ("guilty") in such queues; this benchmark says whether a
device does, and whether the bound or the notification is what decides it."""

from __future__ import annotations

import json
import os
import subprocess
import sys

from ... import scenes
from ...methods import method
from ...methods.core import Param
from .core import Benchmark, register
from .timing import post_process_methods, split

# Each setting's environment, over the caller's: the context's bound on unfinished passes
# (BLURLAB_PASSES_IN_FLIGHT, "" for its default, "0" for none) and whether it asks to be told
# of a reset (BLURLAB_RESET_NOTIFICATION, "0": a plain context, which does not).
SETTINGS = {
    "bounded": {"BLURLAB_PASSES_IN_FLIGHT": "", "BLURLAB_RESET_NOTIFICATION": ""},
    "unbounded": {"BLURLAB_PASSES_IN_FLIGHT": "0", "BLURLAB_RESET_NOTIFICATION": ""},
    "bounded_plain": {"BLURLAB_PASSES_IN_FLIGHT": "", "BLURLAB_RESET_NOTIFICATION": "0"},
    "unbounded_plain": {"BLURLAB_PASSES_IN_FLIGHT": "0", "BLURLAB_RESET_NOTIFICATION": "0"},
}
MISSING = "–"  # a cell the run did not reach: its context was lost before

# One setting on one scene, in a process of its own (its context made with the setting's
# environment): JSON on the last line of its output.
_QUEUE_RUN = """
import json, sys, time
import blurlab as bl
device, scene_name, method, size, issue_s = json.loads(sys.argv[1])
ctx = bl.Context(device)
row = {"bound": ctx.info()["passes_in_flight"], "notification": ctx.info()["reset_notification"]}
try:
    frame = ctx.render(bl.scenes.get(scene_name), tuple(size))
    bl.blur(ctx, frame, method, timed=False)
    with ctx.timer() as one:
        bl.blur(ctx, frame, method, timed=False)
    row["call_ms"] = one.ms
    calls, start = 0, time.perf_counter()
    while time.perf_counter() - start < issue_s:
        bl.blur(ctx, frame, method, timed=False)
        calls += 1
    issued = time.perf_counter()
    with ctx.timer():  # its result is read on leaving: the read that met the resets
        bl.blur(ctx, frame, method, timed=False)
    row.update(calls=calls, issue_s=issued - start, drain_s=time.perf_counter() - issued)
    row["lost"] = "no"
except bl.ContextLost as error:
    row["lost"] = str(error)
row["reset_status"] = ctx.reset_status()
row["pacing_waits"] = ctx.pacing_waits()
print(json.dumps(row))
"""


def _device(ctx):
    """The device the benchmark's context is on, as Context() takes it."""
    index = ctx.info()["device_index"]
    return index if index >= 0 else ctx.info()["device"]


def _queue_run(ctx, setting: str, scene: str, name: str, size, issue_s: float) -> dict:
    arguments = json.dumps([_device(ctx), scene, name, list(size), issue_s])
    done = subprocess.run(
        [sys.executable, "-c", _QUEUE_RUN, arguments],
        env={**os.environ, **SETTINGS[setting]},
        capture_output=True,
        text=True,
        timeout=600,
    )
    if done.returncode != 0:
        raise RuntimeError(
            f"blurlab: queue_depth: the run of {setting!r} on {scene} failed:\n{done.stderr}"
        )
    return json.loads(done.stdout.splitlines()[-1])


def _queue_depth(ctx, size, p, out) -> None:
    chosen = split(p["scenes"])
    unknown = sorted(set(chosen) - set(scenes.names() + scenes.names("failure")))
    if unknown or not chosen:
        raise ValueError(
            f"blurlab: queue_depth scenes {p['scenes']!r}: built-in or failure scenes, "
            "comma-separated"
        )
    one_frame = post_process_methods()
    name = p["method"] or next(n for n in one_frame if method(n).backends == ("fragment",))
    if name not in one_frame:
        raise ValueError(
            f"blurlab: queue_depth method {p['method']!r}: one of {', '.join(one_frame)}"
        )
    settings = split(p["settings"])
    if not settings or set(settings) - set(SETTINGS):
        raise ValueError(
            f"blurlab: queue_depth settings {p['settings']!r}: from {', '.join(SETTINGS)}, "
            "separated by commas"
        )
    rows, lost = [], dict.fromkeys(settings, 0)
    for setting in settings:
        for scene in chosen:
            run = _queue_run(ctx, setting, scene, name, size, p["issue_s"])
            lost[setting] += run["lost"] != "no"
            queued = run["calls"] * run["call_ms"] / 1e3 if "calls" in run else MISSING
            rows.append(
                [
                    setting,
                    scene,
                    run["bound"],
                    run["notification"],
                    run.get("call_ms", MISSING),
                    run.get("calls", MISSING),
                    queued,
                    run.get("drain_s", MISSING),
                    run["pacing_waits"],
                    run["reset_status"],
                    run["lost"],
                ]
            )
    out.table(
        f"{name} issued for {p['issue_s']:g} s without a wait, then a timer read, in a "
        "process of its own per setting and scene",
        [
            ("setting", ""),
            ("scene", ""),
            ("passes in flight", ""),
            ("reset notification", ""),
            ("ms a call", "ms"),
            ("calls issued", ""),
            ("their GPU work", "s"),
            ("wait for the last call", "s"),
            ("pacing waits", ""),
            ("reset status", ""),
            ("context lost", ""),
        ],
        rows,
    )
    for setting, count in lost.items():
        out.figure(f"{setting}: contexts lost, of {len(chosen)}", count, "")


register(
    Benchmark(
        "queue_depth",
        "untimed calls of a slow fragment-pass method issued without a wait, then a timer "
        "read, with and without the bound on unfinished passes and the reset notification: "
        "whether the driver resets the context (docs/spec.md §6.3)",
        {
            "scenes": Param(
                "camera_yaw,near_plane", object, "comma-separated built-in or failure scenes"
            ),
            "method": Param(
                "",
                object,
                "a method that blurs one frame (empty: the one drawn by fragment passes alone, "
                "the slowest on the H100)",
            ),
            "issue_s": Param(0.25, float, "seconds of issuing without a wait", 0.01, 10.0),
            "settings": Param(
                ",".join(SETTINGS),
                object,
                "comma-separated, from bounded (the default bound on unfinished passes), "
                "unbounded (none), and each _plain (a context without reset notification)",
            ),
        },
        _queue_depth,
        {"tiny": (32, 18), "software": (320, 180), "gpu": (1920, 1080)},
        {"tiny": {"scenes": "camera_yaw", "issue_s": 0.05}},
    )
)
