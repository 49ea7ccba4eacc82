"""What a driver does with a deep queue (docs/spec.md §6.3): untimed calls of a slow method
(by default the one drawn by fragment passes alone) issued without a wait for a while, then a
timer read, and a long reference, whose sub-frames' timers are read after the last, each in a
process of its own for each setting of the context's bound on unfinished passes and its reset
notification. The H100's driver reset contexts ("guilty") in such queues; this benchmark says
whether a device does, and whether the bound or the notification is what decides it. What the
bound costs: a short filter's time per call and back to back under each setting."""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

from blurlab.methods import method
from blurlab.methods.params import Param
from blurlab.scene import scenes

from .core import Benchmark, child_environment, register
from .taps import BASELINE
from .timing import post_process_methods, split

# Each setting's environment, over the caller's: the context's bound on unfinished passes
# (BLURLAB_PASSES_IN_FLIGHT, "" for its default, "0" for none; 4 puts a fence after every pass)
# and whether it asks to be told of a reset (BLURLAB_RESET_NOTIFICATION, "0": a plain context,
# which does not).
SETTINGS = {
    "bounded": {"BLURLAB_PASSES_IN_FLIGHT": "", "BLURLAB_RESET_NOTIFICATION": ""},
    "fence_per_pass": {"BLURLAB_PASSES_IN_FLIGHT": "4", "BLURLAB_RESET_NOTIFICATION": ""},
    "unbounded": {"BLURLAB_PASSES_IN_FLIGHT": "0", "BLURLAB_RESET_NOTIFICATION": ""},
    "bounded_plain": {"BLURLAB_PASSES_IN_FLIGHT": "", "BLURLAB_RESET_NOTIFICATION": "0"},
    "unbounded_plain": {"BLURLAB_PASSES_IN_FLIGHT": "0", "BLURLAB_RESET_NOTIFICATION": "0"},
}
MISSING = "–"  # a cell the run did not reach: its context was lost before

# One loop under one setting, in a process of its own (its context made with the setting's
# environment): "calls" issues a method's untimed calls for issue_s, then reads a timer;
# "reference" renders a reference of `samples` sub-frames, whose timers are read once after the
# last (docs/spec.md §11); "cost" times a short filter's calls, each by its passes' timers
# (median of `runs`) and back to back. JSON on the last line of its output.
_QUEUE_RUN = """
import json, sys, time
import blurlab as bl
from blurlab_bench.timing import back_to_back_ms, median_passes
device, loop, scene_name, method, size, issue_s, samples, runs = json.loads(sys.argv[1])
ctx = bl.Context(device)
row = {"bound": ctx.info()["passes_in_flight"], "per_fence": ctx.info()["passes_per_fence"],
       "notification": ctx.info()["reset_notification"]}
try:
    scene = bl.scenes.get(scene_name)
    start = time.perf_counter()
    if loop == "cost":
        frame = ctx.render(scene, tuple(size))
        passes, _ = median_passes(ctx, frame, method, runs)
        row["each_ms"] = passes["total"]
        row["back_to_back_ms"] = back_to_back_ms(
            ctx, lambda: bl.blur(ctx, frame, method, timed=False))
    elif loop == "reference":
        reference = ctx.reference(scene, tuple(size), samples=samples, progress=False)
        row.update(each_ms=reference.ms_per_subframe, issued=samples)
    else:
        frame = ctx.render(scene, tuple(size))
        bl.blur(ctx, frame, method, timed=False)
        with ctx.timer() as one:
            bl.blur(ctx, frame, method, timed=False)
        calls, start = 0, time.perf_counter()
        while time.perf_counter() - start < issue_s:
            bl.blur(ctx, frame, method, timed=False)
            calls += 1
        with ctx.timer():  # its result is read on leaving: the read that met the resets
            bl.blur(ctx, frame, method, timed=False)
        row.update(each_ms=one.ms, issued=calls)
    row["wall_s"] = time.perf_counter() - start
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


def _queue_run(ctx, setting: str, loop: str, scene: str, name: str, size, p) -> dict:
    arguments = json.dumps(
        [
            _device(ctx),
            loop,
            scene,
            name,
            list(size),
            p["issue_s"],
            p["reference_samples"],
            p["runs"],
        ]
    )
    done = subprocess.run(
        [sys.executable, "-c", _QUEUE_RUN, arguments],
        env=child_environment(SETTINGS[setting]),
        capture_output=True,
        text=True,
        timeout=600,
    )
    if done.returncode != 0:
        raise RuntimeError(
            f"blurlab: queue_depth: the {loop} run of {setting!r} on {scene} failed:\n{done.stderr}"
        )
    return json.loads(done.stdout.splitlines()[-1])


def _scenes(text: str, what: str) -> list[str]:
    chosen = split(text)
    known = scenes.names() + scenes.names("failure") + scenes.names("transparency")
    if set(chosen) - set(known):
        raise ValueError(
            f"blurlab: queue_depth {what} {text!r}: built-in, failure or transparency scenes, "
            "comma-separated"
        )
    return chosen


def _queue_depth(ctx, size, p, out) -> None:
    loops = [("calls", scene) for scene in _scenes(p["scenes"], "scenes")]
    loops += [("reference", scene) for scene in _scenes(p["reference_scenes"], "reference_scenes")]
    costs = _scenes(p["cost_scenes"], "cost_scenes")
    if not loops and not costs:
        raise ValueError("blurlab: queue_depth needs scenes, reference_scenes or cost_scenes")
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
    labels = {
        "calls": f"{name} for {p['issue_s']:g} s, then a timer",
        "reference": f"a reference of {p['reference_samples']} sub-frames",
    }
    rows, cost_rows, lost = [], [], dict.fromkeys(settings, 0)
    for setting in settings:
        for loop, scene in loops:
            run = _queue_run(ctx, setting, loop, scene, name, size, p)
            lost[setting] += run["lost"] != "no"
            queued = run["issued"] * run["each_ms"] / 1e3 if "issued" in run else MISSING
            rows.append(
                [
                    setting,
                    labels[loop],
                    scene,
                    run["bound"],
                    run["notification"],
                    run.get("each_ms", MISSING),
                    run.get("issued", MISSING),
                    queued,
                    run.get("wall_s", MISSING),
                    run["pacing_waits"],
                    run["reset_status"],
                    run["lost"],
                ]
            )
        for scene in costs:
            run = _queue_run(ctx, setting, "cost", scene, BASELINE, size, p)
            lost[setting] += run["lost"] != "no"
            cost_rows.append(
                [
                    setting,
                    scene,
                    run["bound"],
                    run["per_fence"],
                    run.get("each_ms", MISSING),
                    run.get("back_to_back_ms", MISSING),
                    run["pacing_waits"],
                    run["lost"],
                ]
            )
    if rows:
        out.table(
            "loops that issue without a wait, each in a process of its own per setting and scene",
            [
                ("setting", ""),
                ("loop", ""),
                ("scene", ""),
                ("passes in flight", ""),
                ("reset notification", ""),
                ("ms each (a call, a sub-frame)", "ms"),
                ("issued", ""),
                ("their GPU work", "s"),
                ("wall of the loop and its read", "s"),
                ("pacing waits", ""),
                ("reset status", ""),
                ("context lost", ""),
            ],
            rows,
        )
    if cost_rows:
        out.table(
            f"what the bound costs: {BASELINE}'s GPU ms per call, by its passes' timers (median "
            f"of {p['runs']}) and over 50 calls back to back, in a process of its own per "
            "setting and scene",
            [
                ("setting", ""),
                ("scene", ""),
                ("passes in flight", ""),
                ("passes per fence", ""),
                ("per call", "ms"),
                ("back to back", "ms"),
                ("pacing waits", ""),
                ("context lost", ""),
            ],
            cost_rows,
        )
    for setting in settings:
        out.figure(f"{setting}: contexts lost, of {len(loops) + len(costs)}", lost[setting], "")
        timed = [row for row in cost_rows if row[0] == setting and row[-1] == "no"]
        for column, what in ((4, "per call"), (5, "back to back")):
            if timed:
                median = statistics.median(row[column] for row in timed)
                out.figure(f"{setting}: {BASELINE} ms {what} (median)", median, "ms")


register(
    Benchmark(
        "queue_depth",
        "loops that issue without a wait (a slow fragment-pass method's untimed calls, then a "
        "timer read; a long reference), with and without the bound on unfinished passes and "
        "the reset notification: whether the driver resets the context, and what the bound "
        "costs a short filter's time (docs/spec.md §6.3)",
        {
            "scenes": Param(
                "camera_yaw,near_plane",
                str,
                "comma-separated built-in, failure or transparency scenes",
            ),
            "method": Param(
                "",
                str,
                "a method that blurs one frame (empty: the one drawn by fragment passes alone, "
                "the slowest on the H100)",
            ),
            "issue_s": Param(0.25, float, "seconds of issuing without a wait", 0.01, 10.0),
            "reference_scenes": Param(
                "smoke_pan",
                str,
                "comma-separated scenes whose reference is rendered under each setting "
                "(empty: none)",
            ),
            "reference_samples": Param(1024, int, "the references' sub-frames", 1, 1024),
            "cost_scenes": Param(
                "occluder,camera_yaw,fast_fan",
                str,
                f"comma-separated scenes where {BASELINE} is timed under each setting (empty: "
                "none)",
            ),
            "runs": Param(10, int, "timed calls per cost scene (their median)", 1, 1000),
            "settings": Param(
                ",".join(SETTINGS),
                str,
                "comma-separated, from bounded (the default bound on unfinished passes), "
                "fence_per_pass (a bound of 4, a fence after every pass), unbounded (none), and "
                "bounded_plain, unbounded_plain (a context without reset notification)",
            ),
        },
        _queue_depth,
        {"tiny": (32, 18), "software": (320, 180), "gpu": (1920, 1080)},
        {
            "tiny": {
                "scenes": "camera_yaw",
                "issue_s": 0.05,
                "reference_samples": 4,
                "cost_scenes": "occluder",
                "runs": 2,
                "settings": "bounded,unbounded_plain",  # both switches, in 6 processes not 15
            },
            "software": {"reference_samples": 256},
        },
    )
)
