"""``feeder cycle`` as separate processes: two runs on one folder at once, and Ctrl-C (SIGINT)
at the worst moments. Nothing is ever half-written, nothing mixes two runs, and the user gets
one line, not a traceback."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from feeder.study.csv import read_csv

from .conftest import REPO

WAIT = 120.0
"""[s] Longest wait for a run to reach a state or to end (a cycle takes ~5 s here; CI's two
cores may be busy with another test)."""
POLL = 0.002
"""[s] Polling step while waiting for a file to appear: writing cycle.csv takes ~0.5 s."""
ROWS = 4001
"""Samples of the default cycle: 4 s at 1 kHz, both ends included (REFERENCE.md)."""


def start(*arguments: str, group: bool = False) -> subprocess.Popen:
    """``python -m feeder ...`` with SIGINT at its default (a shell may start tests with it
    ignored, and Python then keeps it ignored); with ``group``, in a process group of its own,
    as a terminal's foreground job."""
    return subprocess.Popen(
        [sys.executable, "-m", "feeder", *arguments],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        start_new_session=group,
    )


def wait_for(condition, what: str) -> None:
    deadline = time.monotonic() + WAIT
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(POLL)


def finish(process: subprocess.Popen) -> tuple[int, str, str]:
    out, err = process.communicate(timeout=WAIT)
    return process.returncode, out, err


def check_complete(folder) -> dict:
    """The folder's manifest says complete, lists exactly its files, and each hash matches;
    the table is whole."""
    manifest = json.loads((folder / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["complete"] is True
    assert sorted(p.name for p in folder.iterdir()) == sorted(
        [*manifest["files"], "feeder-run.json"]
    )
    for name, digest in manifest["files"].items():
        assert hashlib.sha256((folder / name).read_bytes()).hexdigest() == digest, name
    table = read_csv(folder / "cycle.csv")
    assert len(table["t"]) == ROWS and len(table) == len(set(table))
    return manifest


def test_second_run_on_the_same_folder_is_refused(tmp_path):
    out = tmp_path / "results"
    first = start("cycle", "--elevation", "10", "--out", str(out))
    wait_for(lambda: (out / ".feeder-run.lock").exists(), "the first run's lock")
    second = start("cycle", "--elevation", "20", "--out", str(out))
    status, _, err = finish(second)
    assert status == 2, err
    assert "another feeder run is writing into" in err and "Traceback" not in err
    status, _, err = finish(first)
    assert status == 0, err
    manifest = check_complete(out)
    assert manifest["elevation_deg"] == 10.0  # the first run's outputs, all of them


def test_simultaneous_runs_never_mix(tmp_path):
    """Started together: one runs, the other is refused; the folder is the winner's alone."""
    out = tmp_path / "results"
    runs = {e: start("cycle", "--elevation", e, "--out", str(out)) for e in ("10", "20")}
    results = {e: finish(p) for e, p in runs.items()}
    statuses = sorted(status for status, _, _ in results.values())
    assert statuses == [0, 2], results
    (winner,) = [e for e, (status, _, _) in results.items() if status == 0]
    assert check_complete(out)["elevation_deg"] == float(winner)


def test_ctrl_c_while_computing(tmp_path):
    """Exit 130 with one line; the new folder is removed: nothing looks like a result."""
    out = tmp_path / "results"
    run = start("cycle", "--elevation", "10", "--out", str(out))
    wait_for(lambda: (out / ".feeder-run.lock").exists(), "the run's lock")
    run.send_signal(signal.SIGINT)
    status, _, err = finish(run)
    assert status == 130
    assert len(err.strip().splitlines()) == 1 and "interrupted" in err, err
    assert not out.exists()


@pytest.mark.parametrize("moment", [".feeder-run.lock", ".cycle.csv.*.part"])
def test_ctrl_c_at_the_terminal_stops_the_figure_workers(tmp_path, moment):
    """A terminal's Ctrl-C reaches the whole process group, the figure workers too (while they
    import matplotlib, after the lock; while they draw, as the table is written): still one
    line and status 130, no worker left running, and the folder removed, unless the signal came
    after the last output was in place (the workers end after the outputs are written): then the
    folder holds a complete run."""
    out = tmp_path / "results"
    run = start("cycle", "--elevation", "10", "--out", str(out), group=True)
    wait_for(lambda: any(out.glob(moment)), moment)
    os.killpg(run.pid, signal.SIGINT)
    status, _, err = finish(run)
    assert status == 130
    assert len(err.strip().splitlines()) == 1 and "interrupted" in err, err
    if out.exists():
        check_complete(out)
    wait_for(lambda: not group_alive(run.pid), "the workers to end")


def group_alive(group: int) -> bool:
    """Whether any process of the process group is still running."""
    try:
        os.killpg(group, 0)
    except ProcessLookupError:
        return False
    return True


def test_ctrl_c_while_writing_the_table(tmp_path):
    """Ctrl-C while cycle.csv is being written over an earlier run's: no temporary file is
    left, the earlier table is intact (its hash unchanged), and the manifest says the folder
    is incomplete; the next run completes it."""
    out = tmp_path / "results"
    status, _, err = finish(start("cycle", "--elevation", "10", "--out", str(out), "--no-forward"))
    assert status == 0, err
    before = check_complete(out)["files"]["cycle.csv"]
    run = start("cycle", "--elevation", "20", "--out", str(out), "--no-forward")
    wait_for(lambda: any(out.glob(".cycle.csv.*.part")), "cycle.csv being written")
    run.send_signal(signal.SIGINT)
    status, _, err = finish(run)
    assert status == 130 and "Traceback" not in err, err
    assert len(err.strip().splitlines()) == 1
    assert not list(out.glob(".*"))  # neither a temporary file nor the lock
    assert hashlib.sha256((out / "cycle.csv").read_bytes()).hexdigest() == before
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["complete"] is False
    status, _, err = finish(start("cycle", "--elevation", "20", "--out", str(out), "--no-forward"))
    assert status == 0, err
    assert check_complete(out)["elevation_deg"] == 20.0


def test_ctrl_c_stops_the_viewer_cleanly():
    """Ctrl-C is how ``feeder view`` stops: exit 0, no traceback, once it has said so."""
    viewer = start("view", "--elevation", "30")
    address, prompt = viewer.stdout.readline(), viewer.stdout.readline()
    assert "open http://127.0.0.1:" in address and "press Ctrl-C" in prompt
    viewer.send_signal(signal.SIGINT)
    status, _, err = finish(viewer)
    assert status == 0 and "Traceback" not in err, err


@pytest.mark.parametrize("moment", [".feeder-run.lock", "*.png"])
def test_sigterm_stops_the_run_and_its_workers(tmp_path, moment):
    """``kill PID`` (SIGTERM to the command alone, not its group) once its figure workers run
    (after the lock) or once its first figure is written: status 143 and one line, no process
    of the run left (the workers once lived on, holding the caller's pipes), and no folder that
    looks complete unless it is."""
    out = tmp_path / "results"
    run = start("cycle", "--elevation", "10", "--out", str(out), group=True)
    wait_for(lambda: any(out.glob(moment)), moment)
    run.send_signal(signal.SIGTERM)
    status, _, err = finish(run)
    assert status == 143, err
    assert len(err.strip().splitlines()) == 1 and "terminated (SIGTERM)" in err, err
    if out.exists():
        check_complete(out)
    wait_for(lambda: not group_alive(run.pid), "the workers to end")


def test_sigterm_stops_a_sweep_and_its_workers(tmp_path):
    """``kill PID`` on a running sweep: status 143, one line, none of its workers left."""
    out = tmp_path / "sweep"
    run = start("sweep", "--elevations", "-4", "70", "0.5", "--out", str(out), group=True)
    wait_for(lambda: (out / "sweep_peaks.csv").exists(), "the first rows of the table")
    run.send_signal(signal.SIGTERM)
    status, _, err = finish(run)
    assert status == 143, err
    assert len(err.strip().splitlines()) == 1 and "terminated (SIGTERM)" in err, err
    wait_for(lambda: not group_alive(run.pid), "the workers to end")


@pytest.mark.parametrize("moment", [".feeder-run.lock", "sweep_peaks.csv"])
def test_ctrl_c_at_the_terminal_stops_a_large_sweep_at_once(tmp_path, moment):
    """A terminal's Ctrl-C (SIGINT to the whole group) as a 74 001-case sweep submits its
    batches and forks its workers (the lock), or once it computes (its first checkpoint): one
    line, status 130, and no process of the run left (the whole 74 001 cases would take ~25 min:
    a run that ignored the signal would fail :data:`WAIT`). How soon it stops is a figure of
    ``benchmarks/bench_interrupt.py``, not asserted here: CI's cores may be busy."""
    out = tmp_path / "sweep"
    run = start("sweep", "--elevations", "-4", "70", "0.001", "--out", str(out), group=True)
    wait_for(lambda: (out / moment).exists(), moment)
    os.killpg(run.pid, signal.SIGINT)
    try:
        status, _, err = finish(run)
        wait_for(lambda: not group_alive(run.pid), "the workers to end")
    finally:  # a run that ignored the signal would go on for ~25 min: never leave it behind
        if group_alive(run.pid):
            os.killpg(run.pid, signal.SIGKILL)
    assert status == 130, err
    assert not list(out.glob("*.part")) and not list(out.glob(".*.part"))  # nothing half-written
    assert err.strip().splitlines() == [
        "feeder: interrupted (Ctrl-C); no output was left half-written; an output folder left "
        "behind has its manifest (feeder-run.json) marked incomplete"
    ], err


def test_a_sweep_of_too_many_cases_is_refused_in_one_line(tmp_path):
    """−4° … 70° by 0.0001° (740 001 cases, ~4 h on 2 cores) is refused before any work."""
    out = tmp_path / "sweep"
    run = start("sweep", "--elevations", "-4", "70", "0.0001", "--out", str(out), group=True)
    try:
        status, _, err = finish(run)
    finally:  # accepted, it would run for hours: never leave it behind
        if group_alive(run.pid):
            os.killpg(run.pid, signal.SIGKILL)
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "740001 elevations" in err and "use a larger elevation step" in err, err
    assert not out.exists()
