"""Command line: ``feeder <command> ...`` (also ``python -m feeder``). Parse, check, call, print.

Commands:
    cycle       the main study: loads and reactions of a cycle, cycle.csv and Figs. 4, 8, 10–15
    kinematics  the cycle's kinematics only: cycle.csv (kinematic columns), Figs. 4 and 10
    view        MeshCat viewer of the cycle, or of any mechanism (MODEL --closures F), on
                127.0.0.1, or a static HTML page of it
    parameters  every number of a device with its unit and source (Markdown), or its parameter
                file (TOML, ``--format toml``)
    urdf        regenerate the URDF files from the parameter sets
    errata      the table of the paper's errata measured on the reference cycle (Markdown)
    sweep       peak loads over elevations × parameter variants × devices, resumable
    analyze     any closed-chain mechanism: mobility report, or its loads and every reaction
    simulate    any closed-chain mechanism run forward from rest or given joint rates under
                gravity and its force elements: states, loads, reactions, drift and energy
                balance
    design      designing the geometry: ``design sensitivities``, the derivative and elasticity
                of every peak load with respect to every length and mass, at one elevation and
                as the envelope over elevations; ``design optimize``, the free geometry that
                minimises a peak over every elevation and vehicle case, within the design
                file's bounds and constraints

Each command has a module of its own here: ``add(commands)`` builds its sub-parser from the
shared option groups (:mod:`feeder.cli.options`), so that every command spells ``--device``,
``--params``, ``--elevation`` and ``--out`` alike, and ``run(args) -> int`` checks, calls the
package and prints. Each command
checks all its input before it creates a file or a folder. Every option may be given once.
Bad input exits with status 2 and one line that names it; Ctrl-C exits with status 130 and
SIGTERM with 143, each with one line, and leave no file half-written (:mod:`feeder.outputs`).
"""

from __future__ import annotations

import argparse
import difflib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Sequence

BLAS_THREADS = "1"
"""OpenBLAS threads of a command's process, unless ``OPENBLAS_NUM_THREADS`` says otherwise: set
before NumPy loads (the commands' imports below), since OpenBLAS starts its threads then. Every
matrix of a command is small (a few dozen rows; 120 × 81 for the N = 40 four-bar), where more
threads only wait for each other (:mod:`feeder.chain.blas`), and starting them alone costs 0.08 s
of CPU in every process (NumPy's and SciPy's OpenBLAS each); parallel work is in processes
(``sweep``'s cases, the figure workers)."""

os.environ.setdefault("OPENBLAS_NUM_THREADS", BLAS_THREADS)

from ..exceptions import FeederError, FeederWarning, InputError  # noqa: E402 (after the BLAS)
from . import (  # noqa: E402 (the commands load NumPy: after the BLAS threads are set)
    analyze,
    cycle,
    design,
    errata,
    kinematics,
    parameters,
    simulate,
    sweep,
    urdf,
    view,
)

COMMANDS = (cycle, kinematics, view, parameters, urdf, errata, sweep, analyze, simulate, design)
"""The commands' modules, in the order ``feeder --help`` lists them."""


def parser(command: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser: one sub-parser per module of :data:`COMMANDS`; given the
    ``command`` about to run, the others are bare names (their options, and the modules their
    help quotes, are not loaded: :func:`main` parses one command)."""
    top = argparse.ArgumentParser(
        prog="feeder",
        description="Analysis of the 152 mm SPH M77 ammunition feeding device. SI units, "
        "elevations in degrees. Every command takes --help.",
        allow_abbrev=False,
    )
    commands = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for module in COMMANDS:
        name = module.__name__.rpartition(".")[2]
        if command in (None, name):
            module.add(commands)
        else:
            commands.add_parser(name)
    return top


MALLOC_TRIM_THRESHOLD = 64 * 2**20
"""[B] Free memory a command's process keeps at the top of its heap before glibc's malloc gives
it back to the system (glibc's default: 128 kB, raised as large blocks are freed). The cycles'
arrays are a few hundred kB to a few MB, made and freed by the thousand: each time the heap was
trimmed, the next ones were mapped again page by page (a 75-elevation sweep: 180 000–210 000 page
faults and 0.5–0.75 s of system CPU, against 54 000 and 0.2–0.3 s kept, measured)."""

MALLOC_MMAP_THRESHOLD = 16 * 2**20
"""[B] Blocks larger than this are mapped from the system on their own (and unmapped when freed):
a fixed size, where glibc's moves with the blocks freed, so that the arrays of a cycle come from
the heap every time."""


def keep_freed_memory() -> bool:
    """Set glibc's malloc to keep freed memory for reuse in this process (a command's: run by
    :func:`main`) and the processes it forks (:data:`MALLOC_TRIM_THRESHOLD`,
    :data:`MALLOC_MMAP_THRESHOLD`), unless the user's environment sets malloc's tunables; True
    if it did. Elsewhere than glibc (macOS, musl, Windows) there is no ``mallopt`` to call (or
    one that ignores these) and nothing changes. Workers a pool starts by ``forkserver`` or
    ``spawn`` (where forking is not safe) do not get it."""
    if any(name.startswith(("MALLOC_", "GLIBC_TUNABLES")) for name in os.environ):
        return False
    import ctypes  # NumPy loads it too

    try:
        mallopt = ctypes.CDLL(None).mallopt  # the process's own C library's
    except (OSError, AttributeError, TypeError):  # Windows: no CDLL(None); macOS: no mallopt
        return False
    trim, mmap = -1, -3  # M_TRIM_THRESHOLD, M_MMAP_THRESHOLD (glibc's malloc.h)
    done = mallopt(trim, MALLOC_TRIM_THRESHOLD), mallopt(mmap, MALLOC_MMAP_THRESHOLD)
    return all(done)  # mallopt answers 1 when it took the setting


INTERRUPTED = 130
"""Exit status after Ctrl-C (SIGINT): 128 + the signal's number, as shells report it."""


TERMINATED = 128 + signal.SIGTERM
"""Exit status after SIGTERM (``kill``, a job scheduler's stop): 143, as shells report it."""

STOPPED = (
    "no output was left half-written; an output folder left behind has its manifest "
    "(feeder-run.json) marked incomplete"
)
"""What a stopped run left: each output is whole or absent, and an output folder that is left
(one the run created is removed) has a manifest saying that the run did not finish: it may hold
an earlier run's outputs beside this one's."""


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is, so that it stops as after Ctrl-C: worker pools
    shut down, half-written outputs removed (a KeyboardInterrupt for every cleanup path)."""


def _terminate(signum, frame) -> None:
    raise _Terminated


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line for the terminal: ``feeder: warning: …`` (the package's own), or
    Python's usual form for a library's."""
    if issubclass(category, FeederWarning):
        print(f"feeder: warning: {message}", file=sys.stderr)
    else:
        print(warnings.formatwarning(message, category, filename, lineno, line), file=sys.stderr)


def _check_command(parser: argparse.ArgumentParser, argv: Sequence[str]) -> None:
    """Refuse an unknown command in one line, with the nearest known one (argparse lists all
    of them, without a suggestion)."""
    if not argv or argv[0].startswith("-"):
        return
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if argv[0] in commands.choices:
        return
    near = difflib.get_close_matches(argv[0], list(commands.choices), n=1, cutoff=0.6)
    hint = f"did you mean `feeder {near[0]}`? " if near else ""
    raise InputError(
        f"no command {argv[0]!r}; {hint}commands: {', '.join(commands.choices)} (feeder --help)"
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (2 for bad input, 1 when the file system
    refuses a file, 130 after Ctrl-C)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    keep_freed_memory()
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _terminate) if main_thread else None
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            known = argv[:1] and argv[0] in (m.__name__.rpartition(".")[2] for m in COMMANDS)
            command_parser = parser(argv[0] if known else None)
            _check_command(command_parser, argv)
            args = command_parser.parse_args(argv)
            args.argv = argv
            return args.run(args)
    except FeederError as exc:
        print(f"feeder: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the file system's refusal: a name too long, a full disk, no access
        where = f": {exc.filename}" if exc.filename else ""
        print(f"feeder: error: {exc.strerror or exc}{where}", file=sys.stderr)
        return 1
    except _Terminated:
        print(f"feeder: terminated (SIGTERM); {STOPPED}", file=sys.stderr)
        return TERMINATED
    except KeyboardInterrupt:
        print(f"feeder: interrupted (Ctrl-C); {STOPPED}", file=sys.stderr)
        return INTERRUPTED
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)
