"""Throwaway: cProfile of run_study at --size (not committed)."""

import argparse
import cProfile
import io
import pstats
import shutil
import time
from pathlib import Path

from blurlab.studies.study import run_study

from common import open_context

parser = argparse.ArgumentParser()
parser.add_argument("--device", default="auto")
parser.add_argument("--size", default="1920x1080")
parser.add_argument("--json", default=None)
args = parser.parse_args()
ctx = open_context(args.device)
size = tuple(int(v) for v in args.size.split("x"))
out = Path(args.json).parent / "profiled_study"
profile = cProfile.Profile()
start = time.perf_counter()
profile.enable()
run_study(ctx, size=size, out=out, progress=False)
profile.disable()
print("study wall", time.perf_counter() - start)
text = io.StringIO()
stats = pstats.Stats(profile, stream=text).sort_stats("cumulative")
stats.print_stats(70)
stats.sort_stats("tottime").print_stats(40)
Path(args.json).with_suffix(".txt").write_text(text.getvalue())
for name in ("results.csv", "phases.json"):
    shutil.copy(out / name, Path(args.json).parent / name)
shutil.rmtree(out)
