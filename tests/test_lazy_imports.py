"""``import feeder`` is cheap: the public names load on first use, and nothing imports
matplotlib but the figures (issue 12: the command line's start-up time)."""

from __future__ import annotations

import multiprocessing
import os
import platform
import subprocess
import sys

import pytest

import feeder

from .conftest import REPO


def _modules_after(code: str, full: bool = False) -> set[str]:
    """Top-level modules (every module and submodule if ``full``) imported by ``code`` in a
    fresh interpreter."""
    name = "m" if full else "m.split('.')[0]"
    script = f"import sys\n{code}\nprint(' '.join(sorted({{{name} for m in sys.modules}})))"
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True
    )
    return set(done.stdout.split())


def test_import_feeder_loads_neither_pinocchio_nor_matplotlib():
    loaded = _modules_after("import feeder")
    assert "pinocchio" not in loaded and "matplotlib" not in loaded


def test_a_cycle_study_needs_no_matplotlib():
    loaded = _modules_after(
        "import feeder\nfeeder.run_cycle_study(feeder.load_feeder(), 0.5, "
        "feeder.CycleSpec(rate=100.0), forward=False).columns()"
    )
    assert "pinocchio" in loaded and "matplotlib" not in loaded


def test_figure_writers_load_matplotlib_only_to_draw():
    """feeder.viz.report ships data to the figure workers; drawing happens there."""
    loaded = _modules_after("import feeder.viz.report as r\nr.study_figure_names()")
    assert "matplotlib" not in loaded
    assert "matplotlib" in _modules_after("from feeder.viz import sweep_figure")


def test_design_sensitivities_load_nothing_of_the_optimisation():
    """``feeder design sensitivities`` imports neither the optimisation's modules nor what only
    they use, scipy.stats (~0.3 s). (scipy.optimize is loaded all the same by the whole parser:
    ``simulate``'s options name the singular-pass modes of feeder.chain, whose module imports
    it; the command itself builds its own sub-parser only, and loads no SciPy.)"""
    loaded = _modules_after(
        "import feeder.cli as c\nc.parser()\nimport feeder.design as d\nd.run_sensitivities\n"
        "from feeder.design import outputs, tables",
        full=True,
    )
    assert "feeder.design.outputs" in loaded
    optimisation = {"feeder.design.optimize", "feeder.design.search", "feeder.design.feasibility"}
    assert not (optimisation | {"scipy.stats"}) & loaded
    assert "scipy.stats" in _modules_after("from feeder.design import run_optimization", True)


def test_every_public_name_resolves_to_its_module_object():
    from feeder.outputs import write_cycle_outputs
    from feeder.study.cycle_study import run_cycle_study

    for name in feeder.__all__:
        assert getattr(feeder, name) is not None, name
    assert feeder.write_cycle_outputs is write_cycle_outputs
    assert feeder.run_cycle_study is run_cycle_study
    assert set(feeder.__all__) <= set(dir(feeder))
    assert feeder.viz.__name__ == "feeder.viz"


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_name"):
        feeder.no_such_name  # noqa: B018


def test_a_run_without_figures_loads_no_plotting(tmp_path):
    """``feeder simulate --no-figures`` writes its table and summary without matplotlib (~0.5 s
    of its start-up), and forks no figure process; the same run with figures draws them in a
    process forked before the run (:func:`feeder.viz.mechanism_figures.figure_process`), which
    loads matplotlib there: not in the command's own process. Where this platform cannot fork
    (:func:`feeder.workers.fork_safe`: a fresh interpreter runs one thread, so only the platform
    decides), the figures are drawn in the command's process, which loads matplotlib."""
    four_bar = REPO / "examples" / "four_bar"
    run = (
        "from feeder.cli import main\nmain(['simulate', {model!r}, '--closures', {toml!r}, "
        "'--duration', '0.01', '--samples', '3', '--out', {out!r}{extra}])"
    )
    files = {"model": str(four_bar / "four_bar.urdf"), "toml": str(four_bar / "closures.toml")}
    bare = run.format(**files, out=str(tmp_path / "bare"), extra=", '--no-figures'")
    assert "matplotlib" not in _modules_after(bare)
    assert not list((tmp_path / "bare").glob("*.png"))
    with_figures = _modules_after(run.format(**files, out=str(tmp_path / "all"), extra=""))
    forks = "fork" in multiprocessing.get_all_start_methods()
    assert ("matplotlib" in with_figures) is not forks
    assert (tmp_path / "all" / "motion.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


VIEWER = {"meshcat", "trimesh", "pinocchio.visualize"}
"""What only the viewer and the report page need (0.35–0.39 s, issue 29)."""

FORWARD = {"scipy.integrate"}
"""What only the generic forward and hybrid runs need (0.13 s); the device's own forward run
(:mod:`feeder.dynamics.integrator`) does without it."""

PLOTTING = {"matplotlib"}

SCIPY = {"scipy"}
"""The device's own studies (its cycle, kinematics, sweeps, design sensitivities) use none of
SciPy: only the generic chain's tracking, forward runs and mobility do."""

DEVICE_STUDY = {"feeder.motion", "feeder.paper", "feeder.study.cycle_study", "feeder.viz.report"}
"""What only the device's studies and their figures need: a user mechanism's outputs
(:mod:`feeder.outputs`' tables, figures and report page) load none of it."""

EXAMPLES = REPO / "examples"
FOUR_BAR = [str(EXAMPLES / "four_bar" / "four_bar.urdf"), "--closures"]
FOUR_BAR += [str(EXAMPLES / "four_bar" / "closures.toml")]
SQUEEZER = [str(EXAMPLES / "andrews_squeezer" / "andrews_squeezer.urdf"), "--closures"]
SQUEEZER += [str(EXAMPLES / "andrews_squeezer" / "squeezer.toml")]

COMMANDS = {
    "parameters": (["parameters"], {"pinocchio"} | SCIPY | PLOTTING | VIEWER),
    "urdf": (["urdf", "--out", "{out}"], {"pinocchio"} | SCIPY | PLOTTING | VIEWER),
    "errata": (["errata"], SCIPY | PLOTTING | VIEWER),
    "kinematics": (["kinematics", "--elevation", "30", "--out", "{out}"], SCIPY | VIEWER),
    "kinematics --no-figures": (
        ["kinematics", "--elevation", "30", "--no-figures", "--out", "{out}"],
        SCIPY | PLOTTING | VIEWER,
    ),
    "cycle": (["cycle", "--elevation", "30", "--out", "{out}"], SCIPY | VIEWER),
    "cycle --no-figures": (
        ["cycle", "--elevation", "30", "--no-figures", "--out", "{out}"],
        SCIPY | PLOTTING | VIEWER,
    ),
    "sweep": (["sweep", "--elevations", "0", "10", "10", "--out", "{out}"], SCIPY | VIEWER),
    "analyze": (
        ["analyze", *FOUR_BAR, "--motion", str(EXAMPLES / "four_bar" / "motion.csv")]
        + ["--out", "{out}", "--no-figures"],
        FORWARD | PLOTTING | VIEWER | DEVICE_STUDY,
    ),
    "simulate --no-figures": (
        ["simulate", *SQUEEZER, "--duration", "0.003", "--out", "{out}", "--no-figures"],
        PLOTTING | VIEWER | DEVICE_STUDY,
    ),
    "simulate": (
        ["simulate", *SQUEEZER, "--duration", "0.003", "--samples", "31", "--out", "{out}"],
        {"trimesh"} | DEVICE_STUDY,
    ),
    "design sensitivities --no-figures": (
        ["design", "sensitivities", "--elevation", "30", "--parameter", "L1"]
        + ["--out", "{out}", "--no-figures"],
        SCIPY | PLOTTING | VIEWER,
    ),
}
"""Each command as a user types it, and what it must not import: the plotting only where it
draws in this process (``cycle`` draws in its figure workers), the viewer nowhere but ``view``
and the report pages (and there without trimesh, which only Pinocchio's viser viewer would
use: :mod:`feeder.viz._visualizer`), ``scipy.integrate`` only in the generic forward runs,
the device's studies (:data:`DEVICE_STUDY`) not in a user mechanism's, no SciPy in the device's
studies, and no Pinocchio where a command only prints or writes the device's
numbers."""


@pytest.mark.parametrize("command", list(COMMANDS))
def test_each_command_imports_only_what_it_uses(command, tmp_path):
    argv, absent = COMMANDS[command]
    argv = [word.format(out=tmp_path / "out") for word in argv]
    loaded = _modules_after(f"from feeder.cli import main\nassert main({argv!r}) == 0", full=True)
    assert "feeder.cli" in loaded  # the command ran in that interpreter
    assert not {m for m in loaded for a in absent if m == a or m.startswith(a + ".")}


def _blas_threads(environment: dict[str, str]) -> set[int]:
    """The thread counts of the BLAS libraries loaded by ``import feeder.cli`` in a fresh
    interpreter with ``environment`` (OPENBLAS_NUM_THREADS removed from this one's)."""
    script = (
        "import feeder.cli, numpy, scipy.linalg, threadpoolctl\n"
        "print(' '.join(str(i['num_threads']) for i in threadpoolctl.threadpool_info() "
        "if i['user_api'] == 'blas'))"
    )
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"} | environment
    argv = [sys.executable, "-c", script]
    done = subprocess.run(argv, cwd=REPO, capture_output=True, text=True, check=True, env=env)
    return {int(n) for n in done.stdout.split()}


@pytest.mark.skipif(os.cpu_count() == 1, reason="one core: OpenBLAS starts one thread anyway")
def test_the_command_line_runs_one_blas_thread_unless_told_otherwise():
    """The commands' matrices are small: OpenBLAS is started with one thread (its threads cost
    0.08 s of CPU to start in every process); a user's OPENBLAS_NUM_THREADS is kept."""
    assert _blas_threads({}) == {1}
    assert _blas_threads({"OPENBLAS_NUM_THREADS": "2"}) == {2}


MALLINFO = """
import ctypes, sys
{setup}
import numpy as np

class MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks",
        "fordblks", "keepcost")]

libc = ctypes.CDLL(None)
libc.mallinfo2.restype = MallInfo2
before = libc.mallinfo2().hblkhd
block = np.empty(1 << 20)  # 8 MiB
print(libc.mallinfo2().hblkhd - before)
"""
"""Prints, last, the bytes an 8 MiB array added to malloc's separately mapped blocks (glibc's
``mallinfo2``, 2.33 or later)."""


def _mapped_alone(setup: str, environment: dict[str, str]) -> int:
    argv = [sys.executable, "-c", MALLINFO.format(setup=setup)]
    env = {
        k: v for k, v in os.environ.items() if not k.startswith(("MALLOC_", "GLIBC_TUNABLES"))
    } | environment
    done = subprocess.run(argv, cwd=REPO, capture_output=True, text=True, check=True, env=env)
    return int(done.stdout.split()[-1])


def _glibc() -> tuple[int, ...]:
    """The version of the glibc this interpreter runs on, () elsewhere."""
    name, version = platform.libc_ver()
    return tuple(int(part) for part in version.split(".")) if name == "glibc" else ()


@pytest.mark.skipif(_glibc() < (2, 33), reason="glibc's malloc (its mallinfo2) only")
def test_the_command_line_keeps_freed_memory_in_its_heap():
    """A command's arrays of a few MB come from the heap that keeps freed memory (they were
    mapped and unmapped page by page: 0.5 s of system CPU in a sweep), unless the user's
    environment tunes malloc itself; without a command (importing feeder.cli does not run
    one), glibc maps 8 MiB alone."""
    command = "from feeder.cli import main\nassert main(['parameters']) == 0"
    assert _mapped_alone("import feeder.cli", {}) >= 8 * 2**20
    assert _mapped_alone(command, {}) == 0
    assert _mapped_alone(command, {"MALLOC_ARENA_MAX": "2"}) >= 8 * 2**20


class _NoMallopt:
    """A C library without ``mallopt`` (macOS's, as ``CDLL(None)`` finds it)."""

    def __init__(self, name: None):
        pass


def _windows(name: None) -> None:
    """Windows' ``CDLL(None)``: no library of that name."""
    raise TypeError("argument of type 'NoneType' is not iterable")


@pytest.mark.parametrize("library", [_NoMallopt, _windows], ids=["no-mallopt", "windows"])
def test_malloc_is_left_alone_where_there_is_no_mallopt(monkeypatch, library):
    """Elsewhere than glibc, the command line leaves malloc as it is, and still loads."""
    import ctypes

    from feeder.cli import keep_freed_memory

    for name in [k for k in os.environ if k.startswith(("MALLOC_", "GLIBC_TUNABLES"))]:
        monkeypatch.delenv(name)
    monkeypatch.setattr(ctypes, "CDLL", library)
    assert keep_freed_memory() is False
