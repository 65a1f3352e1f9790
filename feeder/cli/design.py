"""``feeder design``: designing the device's geometry. ``feeder design sensitivities``: the
derivative of every peak load with respect to every length and mass, at one elevation and as
the envelope over an elevation range. ``feeder design optimize``: the free geometry that
minimises a peak over every elevation and vehicle case, within bounds and constraints."""

from __future__ import annotations

import argparse
import sys

from ..design.differences import STEP_FACTOR
from ..design.differentiable import SCALES
from .options import (
    Once,
    add_command,
    command_line,
    device_options,
    elevations_option,
    out_option,
    parallel_options,
    path_argument,
    switch,
    typed,
)

DEVICE_RATE = 1000.0
"""[Hz] The device's sample rate of ``design sensitivities`` without ``--rate``."""


def _exponent(number: float) -> str:
    """``6.06e-6``: three digits, the exponent without padding."""
    mantissa, _, exponent = f"{number:.2e}".partition("e")
    return f"{mantissa}e{int(exponent)}"


def add(commands: argparse._SubParsersAction) -> None:
    """The ``design`` sub-parser and its own sub-commands."""
    about = "designing the geometry: sensitivities of the peaks, and the optimum geometry"
    design = commands.add_parser("design", help=about, description=about, allow_abbrev=False)
    tasks = design.add_subparsers(dest="design_command", required=True, metavar="TASK")
    sensitivities = add_command(
        tasks,
        "sensitivities",
        run,
        "derivatives and elasticities of every peak load with respect to every length and mass",
    )
    elevations_option(
        sensitivities, "none; give this, --elevation, or both", "the envelope's elevations"
    )
    sensitivities.add_argument(
        "--elevation",
        action=Once,
        type=float,
        metavar="DEG",
        help="one elevation ε [deg] to differentiate the peaks at (default: none)",
    )
    out_option(sensitivities)
    device_options(sensitivities, "projectile")
    mechanism_arguments(sensitivities)
    sensitivities.add_argument(
        "--parameter",
        action="append",
        metavar="NAME",
        help="a parameter to differentiate, repeatable (default: every length and link mass; "
        "docs/REFERENCE.md lists them)",
    )
    sensitivities.add_argument(
        "--step",
        action=Once,
        type=float,
        metavar="REL",
        help="relative finite-difference step, in (0, 0.1] (default: ε^(1/3) = "
        f"{_exponent(STEP_FACTOR)} of max(|p|, {SCALES['m']:g} m or {SCALES['kg']:g} kg), "
        "checked by halving)",
    )
    sensitivities.add_argument(
        "--rate",
        action=Once,
        type=float,
        metavar="HZ",
        help=f"the device's sample rate [Hz] (default: {DEVICE_RATE:g})",
    )
    parallel_options(sensitivities)
    switch(
        sensitivities,
        "--no-figures",
        "figures",
        "the tables and the summary only (default: also sensitivities.png)",
    )
    add_optimize(tasks)


def mechanism_arguments(sub: argparse.ArgumentParser, design: bool = True) -> None:
    """MODEL, ``--closures``, ``--motion`` (repeatable) and, if ``design``, ``--design``: a
    mechanism's design instead of the device's (:mod:`feeder.design.mechanism`)."""
    sub.add_argument(
        "model",
        type=path_argument,
        nargs="?",
        metavar="MODEL",
        help="a mechanism's URDF, whose design file's variables are studied (default: the "
        "device); needs --closures, --design and --motion",
    )
    sub.add_argument(
        "--closures",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="the mechanism file (TOML, as feeder analyze takes it), required with MODEL "
        "(default: none)",
    )
    if design:
        sub.add_argument(
            "--design",
            action=Once,
            type=path_argument,
            metavar="FILE",
            help="the mechanism's design file (TOML: variables, objective, constraints), "
            "required with MODEL (default: none; docs/REFERENCE.md)",
        )
    sub.add_argument(
        "--motion",
        action="append",
        type=path_argument,
        metavar="FILE",
        help="a motion table of the mechanism (as feeder analyze takes it), repeatable; the "
        "peaks are over every table's samples; required with MODEL (default: none)",
    )


DEVICE_ONLY = ("elevations", "elevation", "parameter", "rate", "device", "params", "grid",
               "objective")  # fmt: skip
"""Options of the device's design that a mechanism's refuses (its design file says)."""


def _mechanism(args: argparse.Namespace) -> bool:
    """Whether the command is for a mechanism (MODEL given), its options checked."""
    from ..exceptions import InputError

    mechanism = [args.closures, args.design, args.motion]
    if args.model is None:
        if any(value is not None for value in mechanism[::2]):
            raise InputError("--closures and --motion are for a mechanism: give its MODEL too")
        return False
    given = [f"--{name}" for name in DEVICE_ONLY if getattr(args, name, None) is not None]
    if given:
        raise InputError(
            f"{given[0]} is for the device's design; a mechanism's design file names its "
            "variables, objective and constraints"
        )
    for option, value in zip(("--closures", "--design", "--motion"), mechanism, strict=True):
        if value is None:
            raise InputError(f"the design of a mechanism needs {option} FILE")
    return True


def run(args: argparse.Namespace) -> int:
    """Sensitivities of every peak; the tables, the summary, the figure and the manifest."""
    if _mechanism(args):
        return run_mechanism(args)
    from ..design.outputs import run_sensitivities
    from ..design.tables import summary
    from ..motion.laws import CycleSpec
    from ..study.grid import elevation_range
    from .options import params_of

    params = params_of(args)
    elevations = None if args.elevations is None else elevation_range(*args.elevations)
    result, paths = run_sensitivities(
        params,
        args.out,
        elevations_deg=elevations,
        elevation_deg=args.elevation,
        parameters=args.parameter,
        spec=CycleSpec(rate=DEVICE_RATE if args.rate is None else args.rate),
        factor=STEP_FACTOR if args.step is None else args.step,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=True,
        figure=args.figures,
        command=command_line(args),
    )
    return _printed(summary(result) + "\n", paths)


def run_mechanism(args: argparse.Namespace) -> int:
    """A mechanism's sensitivities (:mod:`feeder.design.mechanism.outputs`)."""
    from ..design.mechanism.outputs import run_mechanism_sensitivities
    from ..design.mechanism.sensitivities import summary

    if args.out is None:
        from ..exceptions import InputError

        raise InputError("give the output folder: --out DIR")
    result, paths = run_mechanism_sensitivities(
        args.model,
        args.closures,
        args.design,
        args.motion,
        args.out,
        factor=STEP_FACTOR if args.step is None else args.step,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=True,
        figure=args.figures,
        command=command_line(args),
    )
    return _printed(summary(result) + "\n", paths)


def add_optimize(tasks: argparse._SubParsersAction) -> None:
    """The ``design optimize`` sub-parser."""
    from ..design.problem import DEFAULT_ELEVATIONS, DEFAULT_RATE

    optimize = add_command(
        tasks,
        "optimize",
        run_optimize,
        "the free geometry that minimises a peak over every elevation and vehicle case, within "
        "the design file's bounds and constraints",
    )
    optimize.add_argument(
        "--objective",
        action=Once,
        metavar="NAME",
        help="the device's objective: peak_pressure (the larger chamber's), peak_piston_force, "
        "peak_forearm_moment, any peak of sweep_peaks.csv, or weighted:NAME=W,NAME=W (each "
        "relative to the device as given) (default: peak_pressure; a mechanism's is in its "
        "design file)",
    )
    optimize.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        metavar="DIR",
        help="output folder, required unless --print-design (default: none): new, empty, or "
        "one an earlier feeder run wrote; an interrupted optimisation there is resumed",
    )
    optimize.add_argument(
        "--design",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="design file (TOML): the device's free parameters and their bounds, fixed ones, "
        "constraints and limits (default: the built-in one, --print-design); with MODEL, the "
        "mechanism's variables, objective and constraints (required)",
    )
    switch(optimize, "--print-design", "print_design", "print the built-in design file and "
           "exit (default: optimise)")  # fmt: skip
    elevations_option(optimize, f"the grid's, else {typed(DEFAULT_ELEVATIONS)}")
    optimize.add_argument(
        "--grid",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="sweep grid (TOML) whose variants are the vehicle cases, and whose elevations and "
        "timing apply unless given here; its devices are not used (default: none, standing "
        "level)",
    )
    optimize.add_argument(
        "--rate",
        action=Once,
        type=float,
        metavar="HZ",
        help=f"sample rate of every cycle [Hz] (default: the grid's, else {DEFAULT_RATE:g})",
    )
    device_options(optimize, "projectile")
    optimize.add_argument(
        "--samples",
        action=Once,
        type=int,
        metavar="N",
        help="points of the global start (Latin hypercube; default: 8 per variable that loads "
        "depend on, or the mechanism design file's [search] samples; 0: none)",
    )
    optimize.add_argument(
        "--starts",
        action=Once,
        type=int,
        metavar="N",
        help="local searches (SLSQP), from the best points of the global start (default: 1, "
        "or the mechanism design file's [search] starts)",
    )
    parallel_options(optimize)
    mechanism_arguments(optimize, design=False)
    switch(optimize, "--no-figures", "figures", "no optimum.png (default: written)")
    switch(
        optimize,
        "--no-sensitivities",
        "sensitivities",
        "no sensitivities at the optimum (default: sensitivities.csv for the variables)",
    )


def run_optimize(args: argparse.Namespace) -> int:
    """The optimum geometry; its parameter file, tables, figure, history and manifest."""
    from ..design.design_space import BUILT_IN
    from ..design.optimize import run_optimization
    from ..exceptions import InputError
    from ..motion.laws import CycleSpec
    from ..study.grid import elevation_range
    from ..study.grid_file import read_grid
    from .options import params_of

    if args.print_design:
        print(BUILT_IN, end="")
        return 0
    if args.out is None:
        raise InputError("give the output folder: --out DIR (or --print-design)")
    if _mechanism(args):
        return run_mechanism_optimize(args)
    params = params_of(args)
    grid = None if args.grid is None else read_grid(args.grid)
    spec = None
    if args.rate is not None:
        durations = grid.spec.durations if grid is not None else CycleSpec.durations
        spec = CycleSpec(durations=durations, rate=args.rate)
    elevations = None if args.elevations is None else elevation_range(*args.elevations)
    return _optimized(
        args,
        lambda: run_optimization(
            params,
            args.out,
            objective=args.objective or "peak_pressure",
            design=args.design,
            elevations_deg=elevations,
            grid=grid,
            spec=spec,
            samples=args.samples,
            starts=1 if args.starts is None else args.starts,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=True,
            figure=args.figures,
            sensitivities=args.sensitivities,
            command=command_line(args),
        ),
    )


def run_mechanism_optimize(args: argparse.Namespace) -> int:
    """A mechanism's optimum (:func:`~feeder.design.mechanism.run_mechanism_optimization`)."""
    from ..design.mechanism.optimize import run_mechanism_optimization

    return _optimized(
        args,
        lambda: run_mechanism_optimization(
            args.model,
            args.closures,
            args.design,
            args.motion,
            args.out,
            samples=args.samples,
            starts=args.starts,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=True,
            figure=args.figures,
            command=command_line(args),
        ),
    )


def _optimized(args: argparse.Namespace, optimise) -> int:
    """Run ``optimise()`` (the device's or a mechanism's optimisation: (optimum, paths)), print
    its summary and the files written; on Ctrl-C say where the best point so far was written."""
    from ..design.report import INTERRUPTED

    try:
        optimum, paths = optimise()
    except KeyboardInterrupt:
        if _status(args.out) == INTERRUPTED:
            print(f"feeder: {INTERRUPTED}: written in {args.out}", file=sys.stderr)
        raise
    _printed((paths[0].parent / "summary.txt").read_text(encoding="utf-8"), paths)
    return 0 if optimum.best is not None else 1


def _printed(summary: str, paths) -> int:
    """Print ``summary`` and the files written (``paths``, the first in the output folder, a
    subfolder's counted: ``meshes/ (3 files)``); 0, the exit status."""
    print(summary, end="")
    folder = paths[0].parent
    names = [path.name for path in paths if path.parent == folder]
    inner = [path.relative_to(folder).parts[0] for path in paths if path.parent != folder]
    names += [f"{name}/ ({inner.count(name)} files)" for name in dict.fromkeys(inner)]
    print(f"wrote {', '.join(names)} in {folder}")
    return 0


def _status(folder) -> str | None:
    """The status an optimisation's manifest in ``folder`` records, if any."""
    import json

    from ..files import MANIFEST

    try:
        return json.loads((folder / MANIFEST).read_text(encoding="utf-8")).get("status")
    except (OSError, ValueError):
        return None
