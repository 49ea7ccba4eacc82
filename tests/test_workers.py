"""The study's chart processes (blurlab.studies.workers): jobs run in children started as
`python -m blurlab.studies.workers`, answers and errors come back, and a script without a
main guard can use them (multiprocessing's spawn would re-run it)."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time

import pytest

from blurlab.studies import workers


def test_jobs_run_in_other_processes_and_their_errors_come_back():
    with workers.ProcessWorkers(2, warm_up=os.getpid) as pool:
        pids = {pool.submit(os.getpid).result() for _ in range(6)}
        assert os.getpid() not in pids and 1 <= len(pids) <= 2
        assert pool.submit(pow, 2, 10).result() == 1024
        assert pool.submit(print, "stray text a job prints").result() is None  # not an answer
        assert pool.submit(pow, 3, 3).result() == 27  # the answers were not corrupted
        with pytest.raises(ValueError, match="invalid literal"):
            pool.submit(int, "x").result()
        with pytest.raises(RuntimeError, match="unpicklable ok"):
            pool.submit(threading.Lock).result()


def test_a_dead_child_fails_its_job_and_the_last_one_fails_the_rest():
    with workers.ProcessWorkers(1) as pool:
        assert pool.submit(pow, 2, 3).result() == 8
        with pytest.raises(RuntimeError, match="ended with code 3"):
            pool.submit(os._exit, 3).result(timeout=60)
        with pytest.raises(RuntimeError, match="before it answered"):
            pool.submit(pow, 2, 3).result(timeout=60)  # no child left: fails, does not hang


def close_answers_then_exit(code: int) -> None:
    """In a child: closes every descriptor but the standard three (its answers' pipe among
    them), lingers, then exits with `code`."""
    os.closerange(3, 4096)
    time.sleep(1.0)
    os._exit(code)


def test_a_child_that_closes_its_pipe_before_it_exits_reports_its_code():
    # The pipe closes a moment before the process ends (poll() still None): seen on a loaded
    # machine, where the message once said "code None".
    with workers.ProcessWorkers(1) as pool:
        with pytest.raises(RuntimeError, match="ended with code 4 before it answered"):
            pool.submit(close_answers_then_exit, 4).result(timeout=60)


def test_bad_process_counts_are_refused():
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(ValueError, match="processes must be an integer >= 1"):
            workers.ProcessWorkers(bad)


def test_a_script_without_a_main_guard_can_draw_its_charts_in_processes(tmp_path):
    script = tmp_path / "unguarded.py"
    script.write_text(
        "from blurlab.studies import workers\n"
        "with workers.ProcessWorkers(2) as pool:\n"
        "    print(sum(f.result() for f in [pool.submit(pow, 2, n) for n in range(4)]))\n"
    )
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=120, check=True
    )
    assert done.stdout.strip() == "15"
