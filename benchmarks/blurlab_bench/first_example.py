"""The first example a newcomer runs: README's "Ten lines" and docs/quickstart.md, which must
show this very code (tests/test_docs.py checks it). The benchmark runs it as a user would, in a
fresh Python process in an empty folder, and records its wall time, start to end, imports
included, and that the columns its comment names are the table's."""

from __future__ import annotations

import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

from blurlab.methods import example_method
from blurlab.methods.params import Param

from .core import Benchmark, register

EXAMPLE = """\
import blurlab as bl

ctx = bl.Context()                        # "auto": GPU if EGL finds one, else llvmpipe
print(ctx.info()["renderer"])
scene = bl.scenes.teapot_pass()           # or bl.Scene(...).add(mesh, material, motion)
frame = ctx.render(scene, (320, 180))     # .color, .depth, .motion: NumPy, read when asked
out = bl.blur(ctx, frame, "{method}", k=20, samples=15)
ref = ctx.reference(scene, (320, 180), samples=64)
print(bl.metrics.psnr(ref.color, out.color), out.timings)  # each pass's ms and its clock
table = bl.sweep(ctx, ["teapot_pass"], size=(160, 90))  # pandas: method, params, total_ms, psnr
bl.plots.save(bl.plots.pareto(table, "teapot_pass"), "pareto.png")
""".replace("{method}", example_method())  # the method examples run, a tile filter with k
GOAL_S = 15.0  # what the example may take on a 2-core machine with llvmpipe


def documented_columns() -> list[str]:
    """The columns the example's comment says the sweep's table has."""
    return re.search(r"# pandas: (.*)", EXAMPLE).group(1).split(", ")


def run_example(folder: str) -> tuple[float, str]:
    """(wall seconds, the renderer it printed) of EXAMPLE in a fresh process in `folder`;
    raises unless it wrote pareto.png and its table has the documented columns."""
    check = f"\nmissing = set({documented_columns()!r}) - set(table.columns)\n"
    check += "assert not missing, f'the comment names columns the table lacks: {missing}'\n"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    start = time.perf_counter()
    result = subprocess.run(
        [sys.executable, "-c", EXAMPLE + check],
        cwd=folder,
        capture_output=True,
        text=True,
        env=env,
    )
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(f"blurlab: the first example failed:\n{result.stderr[-3000:]}")
    if not os.path.getsize(os.path.join(folder, "pareto.png")):
        raise RuntimeError("blurlab: the first example wrote an empty pareto.png")
    return seconds, result.stdout.splitlines()[0]


def _first_example(ctx, size, p, out) -> None:
    renderer = ctx.info()["renderer"]
    load_before = os.getloadavg()[0]
    seconds = []
    for _ in range(p["runs"]):
        with tempfile.TemporaryDirectory() as folder:
            wall, printed = run_example(folder)
        if printed != renderer:
            raise RuntimeError(
                f"blurlab: the example ran on {printed!r}, not on this benchmark's {renderer!r}"
            )
        seconds.append(wall)
    out.figure("wall time, median of the runs", statistics.median(seconds), "s")
    out.figure("wall time, fastest run", min(seconds), "s")
    out.figure(f"goal: at most {GOAL_S:g} s on 2 cores with llvmpipe", GOAL_S, "s")
    # Other processes on the machine slow it down: the load says how busy it was.
    out.figure("load average (1 min) before the runs", load_before, "processes")
    out.figure("load average (1 min) after the runs", os.getloadavg()[0], "processes")
    out.figure("CPU cores", len(os.sched_getaffinity(0)), "cores")


register(
    Benchmark(
        "first_example",
        "README's ten lines (docs/quickstart.md) as a user runs them: a fresh Python process, "
        "imports included, a 320x180 frame and reference, a 160x90 sweep of one scene and "
        "its Pareto chart; wall seconds",
        {"runs": Param(3, int, "runs of the example (the median and the fastest)", 1, 20)},
        _first_example,
        presets={"tiny": {"runs": 1}},
    )
)
