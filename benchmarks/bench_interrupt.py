"""Benchmark: how soon a terminal's Ctrl-C ends a large sweep and every one of its workers.

``tests/test_cli_processes.py`` asserts the behaviour (status 130, one line, no process of the
run left, nothing half-written); this script measures the time, which depends on how busy the
machine is. A 74 001-case sweep (−4° … 70° by 0.001°, ~25 min on two cores) is started in a
process group of its own, as a terminal's foreground job; once it has written its first
checkpoint (``sweep_peaks.csv``), SIGINT goes to the whole group, and the clock runs until no
process of the group is left.

Each worker ends its batch and the one queued for it (2 × 16 cases of ~42 ms: ~1.5 s on free
cores). The reference, measured in the same run, is the start-up of a bare interpreter that
imports what every worker imports (``python -c "import pinocchio, numpy, scipy"``), so the
ratio survives a busy or slower machine better than seconds do. Goal: the stop within
10 × that start-up (about 2 s on free cores).

Run: ``python benchmarks/bench_interrupt.py [--runs 3]``.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
GOAL = 10.0
"""Stop time over the start-up reference (module docstring)."""
WAIT = 300.0
"""[s] Longest wait for the first checkpoint or for the group to end."""


def group_alive(group: int) -> bool:
    try:
        os.killpg(group, 0)
    except ProcessLookupError:
        return False
    return True


def wait_for(condition, what: str) -> None:
    deadline = time.monotonic() + WAIT
    while not condition():
        if time.monotonic() > deadline:
            raise SystemExit(f"bench_interrupt: timed out waiting for {what}")
        time.sleep(0.002)


def start_up() -> float:
    """[s] Wall time of ``python -c "import pinocchio, numpy, scipy"``."""
    begin = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import pinocchio, numpy, scipy"], check=True)
    return time.perf_counter() - begin


def stop_time() -> float:
    """[s] From SIGINT to the whole sweep's process group gone."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "sweep"
        run = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "feeder",
                "sweep",
                "--elevations",
                "-4",
                "70",
                "0.001",
                "--out",
                str(out),
            ],
            cwd=REPO,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
            start_new_session=True,
        )
        try:
            wait_for(lambda: (out / "sweep_peaks.csv").exists(), "the first checkpoint")
            os.killpg(run.pid, signal.SIGINT)
            interrupted = time.perf_counter()
            run.wait(timeout=WAIT)
            wait_for(lambda: not group_alive(run.pid), "the workers to end")
            return time.perf_counter() - interrupted
        finally:
            if group_alive(run.pid):
                os.killpg(run.pid, signal.SIGKILL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="interleaved runs (default 3)")
    runs = parser.parse_args().runs
    stops, starts = [], []
    for _ in range(runs):
        starts.append(start_up())
        stops.append(stop_time())
    stop, reference = statistics.median(stops), statistics.median(starts)
    ratio = stop / reference
    print(f"start-up reference (median of {runs}): {reference:.3f} s")
    print(
        f"Ctrl-C to the last worker gone (median of {runs}): {stop:.3f} s "
        f"(runs: {', '.join(f'{s:.2f}' for s in stops)})"
    )
    print(
        f"ratio {ratio:.1f} × the start-up; goal ≤ {GOAL:g} ×: "
        f"{'PASS' if ratio <= GOAL else 'MISS'}"
    )


if __name__ == "__main__":
    main()
