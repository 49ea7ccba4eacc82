"""A sweep that kills itself with SIGKILL at a chosen point, for tests/test_sweep_faults.py.

    python tests/sweep_kill_job.py OUT.csv ROWS [CUT]

Runs SWEEP into OUT.csv. After ROWS rows have been appended to the file (the first row, which
creates the file, is not counted; 0: never), it sends itself SIGKILL; with CUT (a fraction in
(0, 1)), the killing append first writes only that fraction of its line, as a power cut or a
full disk would leave it. The kill comes from inside the process, at a row count, so every
run of the test kills at the same points.
"""

from __future__ import annotations

import os
import pathlib
import signal
import sys

SCENES = ["fan", "crossing"]
OPTIONS = {
    "size": (32, 18),
    "reference_samples": 8,
    "metrics": ["psnr", "ssim"],
    "progress": False,
    "repeats": 1,
    "readback_batch": 1,  # a row reaches the file as soon as it is made
}


class _KillingFile:
    """An appending file that kills the process at its `rows`-th write."""

    def __init__(self, file, rows: int, cut: float | None):
        self._file, self._left, self._cut = file, rows, cut

    def write(self, data: bytes) -> int:
        self._left -= 1
        if self._left == 0:
            if self._cut is not None:
                self._file.write(data[: max(1, int(len(data) * self._cut))])
            else:
                self._file.write(data)
            os.kill(os.getpid(), signal.SIGKILL)
        return self._file.write(data)

    def __getattr__(self, name):
        return getattr(self._file, name)


def main(out: str, rows: int, cut: float | None) -> None:
    if rows > 0:
        opened = pathlib.Path.open

        def open_killing(self, mode="r", *args, **kwargs):
            file = opened(self, mode, *args, **kwargs)
            return _KillingFile(file, rows, cut) if mode == "ab" else file

        pathlib.Path.open = open_killing
    from method_picks import pick

    import blurlab as bl

    # A gather with taps (tests/method_picks.py: this script sits beside it, on its path).
    grid = {pick(kind="gather", params=("taps",)): {"taps": [2, 4, 6, 8]}}
    bl.sweep(bl.Context(), SCENES, grid, out=out, **OPTIONS)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), float(sys.argv[3]) if len(sys.argv) > 3 else None)
