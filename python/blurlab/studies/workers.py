"""Worker processes for the study's matplotlib charts: an Executor whose jobs run in processes
started as `python -m blurlab.studies.workers`.

matplotlib holds the GIL while it draws, so threads cannot overlap it with the study's own
work. multiprocessing's spawn would, but it re-runs the caller's main script in each child,
which breaks any script that calls `run_study` without an `if __name__ == "__main__":` guard
(and fork is unsafe beside a GL context). These children import only blurlab and take their
jobs, a pickled (function, args, kwargs), one at a time on stdin; they answer on stdout.
"""

from __future__ import annotations

import concurrent.futures
import os
import pickle
import queue
import subprocess
import sys
import threading

STOP_SECONDS = 30  # how long shutdown waits for a child to exit before killing it
LOST_SECONDS = 5  # how long a child whose pipe closed gets to exit, so its exit code is known


class ProcessWorkers(concurrent.futures.Executor):
    """`processes` child processes; submit() queues a call of a module-level function (it and
    its arguments must pickle), any free child runs it. Each child first runs `warm_up` (a
    module-level function, e.g. one that imports matplotlib) while it would be idle anyway."""

    def __init__(self, processes: int, warm_up=None):
        if isinstance(processes, bool) or not isinstance(processes, int) or processes < 1:
            raise ValueError(
                f"blurlab ProcessWorkers: processes must be an integer >= 1, not {processes!r}"
            )
        self._jobs: queue.SimpleQueue = queue.SimpleQueue()
        self._lock = threading.Lock()
        self._alive = processes
        # The children see the modules this process sees, whatever put them on its path.
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
        self._children = [
            subprocess.Popen(
                [sys.executable, "-m", "blurlab.studies.workers"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                env=env,
            )
            for _ in range(processes)
        ]
        self._feeders = [
            threading.Thread(target=self._feed, args=(child, warm_up), daemon=True)
            for child in self._children
        ]
        for feeder in self._feeders:
            feeder.start()

    def submit(self, fn, /, *args, **kwargs) -> concurrent.futures.Future:
        future: concurrent.futures.Future = concurrent.futures.Future()
        self._jobs.put((future, fn, args, kwargs))
        return future

    def _feed(self, child: subprocess.Popen, warm_up) -> None:
        """Hands jobs to one child, one at a time, until shutdown puts None. A child that dies
        fails the job it had and takes no more; once none is left, every job fails at once
        instead of waiting forever."""
        lost = warm_up is not None and _call(child, (warm_up, (), {}))[0] == "lost"
        if lost and not self._one_lost():
            return
        while True:
            job = self._jobs.get()
            if job is None:
                return
            future, fn, args, kwargs = job
            if not future.set_running_or_notify_cancel():
                continue
            outcome, value = ("lost", None) if lost else _call(child, (fn, args, kwargs))
            if outcome == "ok":
                future.set_result(value)
            elif outcome == "error":
                future.set_exception(value)
            else:
                future.set_exception(RuntimeError(_lost_message(child)))
                if not lost:
                    lost = True
                    if not self._one_lost():
                        return

    def _one_lost(self) -> bool:
        """Counts a lost child; True when it was the last one alive."""
        with self._lock:
            self._alive -= 1
            return self._alive == 0

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        if cancel_futures:
            while True:
                try:
                    job = self._jobs.get_nowait()
                except queue.Empty:
                    break
                if job is not None:
                    job[0].cancel()
        for _ in self._feeders:
            self._jobs.put(None)
        for feeder in self._feeders:
            feeder.join()
        for child in self._children:
            child.stdin.close()  # end of jobs: the child's loop ends
            try:
                child.wait(STOP_SECONDS)
            except subprocess.TimeoutExpired:
                child.kill()
                child.wait()
            child.stdout.close()


def _lost_message(child: subprocess.Popen) -> str:
    """What became of a child whose pipe closed. Its pipe can close a moment before the process
    has exited, when poll() still says None (seen on a loaded 2-core machine), so it is given
    LOST_SECONDS to exit."""
    try:
        code = child.wait(LOST_SECONDS)
    except subprocess.TimeoutExpired:
        return (
            f"blurlab: a chart process (pid {child.pid}) closed its pipe before it answered "
            f"and was still running {LOST_SECONDS} s later"
        )
    return f"blurlab: a chart process (pid {child.pid}) ended with code {code} before it answered"


def _call(child: subprocess.Popen, job) -> tuple[str, object]:
    """("ok", result), ("error", exception) or ("lost", None) when the child is gone."""
    try:
        pickle.dump(job, child.stdin)
        child.stdin.flush()
        return pickle.load(child.stdout)
    except (BrokenPipeError, EOFError, OSError):
        return "lost", None


def main() -> None:
    """A child's loop: jobs from stdin until it closes, each answer pickled to stdout. Output
    meant for the console (prints, warnings, C libraries) goes to stderr instead, so that it
    cannot corrupt the answers."""
    answers = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    jobs = sys.stdin.buffer
    while True:
        try:
            fn, args, kwargs = pickle.load(jobs)
        except EOFError:
            return
        try:
            answer = ("ok", fn(*args, **kwargs))
        except Exception as error:  # handed back to the caller's future
            answer = ("error", error)
        try:
            data = pickle.dumps(answer)
        except Exception as error:  # an answer that cannot travel still gets an answer
            data = pickle.dumps(("error", RuntimeError(f"unpicklable {answer[0]}: {error}")))
        answers.write(data)
        answers.flush()


if __name__ == "__main__":
    main()
