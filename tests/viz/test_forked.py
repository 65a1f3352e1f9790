"""Figures drawn in a forked process (feeder.viz.forked, feeder.viz.mechanism_figures): the same
bytes as drawn here, with matplotlib imported lean there; the work's error raised here; a process
never asked ends with its context. Each runs in a fresh, single-threaded interpreter (pytest runs
threads, where nothing forks)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from ..conftest import REPO

MECHANISM = """
import os, sys
from functools import partial
from feeder.viz.mechanism_figures import figure_process, stack_pngs
from feeder.viz.panels import simulation_stacks
from feeder.study.simulate import simulate_mechanism
with figure_process() as drawing:
    unasked = drawing._child.pid
try:
    os.waitpid(unasked, os.WNOHANG)
except ChildProcessError:
    print("ended")
with figure_process() as drawing:
    try:
        drawing.submit(partial(int, "not a number"))()
    except ValueError as error:
        print("raised:", error)
with figure_process(False) as drawing:
    print("not forked" if drawing._child is None else "forked")
with figure_process() as drawing:
    assert drawing._child is not None  # forked before the run (which starts tqdm's thread)
    simulation = simulate_mechanism(sys.argv[1], 0.2, samples=41)
    stacks = simulation_stacks(simulation)
    there = drawing.submit(partial(stack_pngs, stacks))()
print("unloaded" if "matplotlib" not in sys.modules else "loaded")
import matplotlib.lines
print("kept" if "linewidth" in matplotlib.lines.Line2D.set.__doc__ else "short")
here = stack_pngs(stacks)
print("same" if there == here and sorted(there) == sorted(stacks) else "different")
"""


def test_a_mechanisms_figures_drawn_in_a_forked_process_are_drawn_here_byte_for_byte():
    """The forward run's figures drawn by the process forked before the run (which imported
    matplotlib without the artists' set() docstrings) are the ones this process draws with its
    docstrings whole; matplotlib was never loaded here before."""
    closures = REPO / "examples" / "four_bar" / "closures.toml"
    argv = [sys.executable, "-c", MECHANISM, str(closures)]
    done = subprocess.run(argv, capture_output=True, text=True, check=True, cwd=REPO)
    lines = done.stdout.splitlines()
    assert lines[0] == "ended" and lines[2] == "not forked", done.stdout + done.stderr
    assert lines[1].startswith("raised: invalid literal for int()"), lines
    assert lines[3:] == ["unloaded", "kept", "same"], lines


UNREAD = """
import os
from functools import partial
from feeder.viz.forked import FigureProcess, ForkedDrawing

def fds():
    return sorted(os.listdir("/proc/self/fd"))

before = fds()
for failing in (False, True):
    try:
        with FigureProcess() as drawing:
            pid = drawing._child.pid
            drawing.submit(partial(bytes, 1 << 20))  # an answer larger than a pipe holds
            if failing:
                raise ValueError("an output failed before the figures were asked for")
    except ValueError:
        pass
    try:
        os.waitpid(pid, os.WNOHANG)
        print("not reaped")
    except ChildProcessError:
        print("reaped")
print("closed" if fds() == before else f"open: {before} {fds()}")
child = ForkedDrawing(work=partial(bytes, 1 << 20))
first, second = child.answer(), child.answer()
print("twice" if first == second == (True, bytes(1 << 20)) else "once")
child.stop()  # read already: nothing to stop
def broken():
    raise OSError("no fork here")
os.fork = broken
try:
    ForkedDrawing()
except OSError:
    pass
print("closed" if fds() == before else f"open: {before} {fds()}")
"""


@pytest.mark.skipif(not Path("/proc/self/fd").is_dir(), reason="lists open files in /proc")
def test_a_context_left_with_an_unread_answer_leaves_no_process_and_no_pipe():
    """A forked process whose answer (1 MB: more than a pipe holds, so it waits to write it) is
    never read, the context left normally or by an error, is stopped and reaped, its pipes
    closed; an answer read twice is the same; a failed fork leaves no pipe open."""
    done = subprocess.run(
        [sys.executable, "-c", UNREAD], capture_output=True, text=True, check=True, cwd=REPO
    )
    lines = done.stdout.splitlines()
    assert lines == ["reaped", "reaped", "closed", "twice", "closed"], done.stdout + done.stderr
