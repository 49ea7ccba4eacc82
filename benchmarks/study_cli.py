"""`blurlab study` as a user runs it (issue 19's 30-second goal): the command line in a fresh
process, --runs times, each run's process wall clock (interpreter start, imports, GL context
and the study) beside the study's own clock and phases (phases.json).

    python benchmarks/study_cli.py [--device gpu] [--size 1920x1080] [--runs 3] [--json f]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import describe, open_context, save


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--device", default="auto")
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--json", default=None)
    args = parser.parse_args()
    record = describe(open_context(args.device))  # which device; the runs open their own
    record.update({"size": args.size, "runs": []})
    print("\n| run | process wall, s | study clock, s | phases, s |\n|---|---|---|---|")
    for run in range(args.runs):
        with tempfile.TemporaryDirectory() as folder:
            command = [sys.executable, "-m", "blurlab", "--device", args.device, "study"]
            command += ["--size", args.size, "--out", folder]
            start = time.perf_counter()
            subprocess.run(command, check=True, capture_output=True, text=True)
            wall = time.perf_counter() - start
            phases = json.loads((Path(folder) / "phases.json").read_text())
        record["runs"].append({"process_wall_s": wall, **phases})
        shown = ", ".join(f"{k} {v:.1f}" for k, v in phases["phases_s"].items())
        print(f"| {run} | {wall:.1f} | {phases['total_s']:.1f} | {shown} |", flush=True)
    walls = [r["process_wall_s"] for r in record["runs"]]
    clocks = [r["total_s"] for r in record["runs"]]
    record["median_process_wall_s"] = statistics.median(walls)
    record["median_study_s"] = statistics.median(clocks)
    print(
        f"median: process {statistics.median(walls):.1f} s, study {statistics.median(clocks):.1f} s"
    )
    save(args.json, record)


if __name__ == "__main__":
    main()
