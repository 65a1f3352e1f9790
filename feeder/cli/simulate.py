"""``feeder simulate``: a user's closed-chain mechanism run forward from its assembled pose, at
rest or at given joint rates (``--rate JOINT=VALUE``), its ``[[control]]`` joints (or a
``--control`` file's) under control: states.csv, summary, figures, report.html."""

from __future__ import annotations

import argparse

from ..exceptions import InputError
from .options import (
    Once,
    add_command,
    command_line,
    figures_switch,
    mechanism_options,
    path_argument,
    rate_argument,
    wrote,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``simulate`` sub-parser."""
    from ..chain.dynamics.budget import MAX_STEPS, SAMPLE_BYTES, SAMPLE_MEMORY
    from ..chain.dynamics.forward import ATOL, METHODS, RTOL
    from ..chain.dynamics.singular import MODES
    from ..study.simulate import SAMPLES

    simulate = add_command(
        commands,
        "simulate",
        run,
        "any closed-chain mechanism run forward from rest or given joint rates: states, loads, "
        "reactions, energy",
    )
    mechanism_options(simulate)
    simulate.add_argument(
        "--duration",
        action=Once,
        type=float,
        required=True,
        metavar="SECONDS",
        help=f"length of the run [s], required; a run stops after {MAX_STEPS} integration "
        "steps (a few minutes), naming the time it reached; a progress line with an estimate of "
        "the time left shows on a terminal after a few seconds",
    )
    simulate.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        required=True,
        metavar="DIR",
        help="output folder for states.csv, summary.txt and the figures, required",
    )
    simulate.add_argument(
        "--forces",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="TOML file of more [[force]] elements (default: the mechanism file's only)",
    )
    simulate.add_argument(
        "--control",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="TOML file of [[control]] tables, instead of the mechanism file's: each drives an "
        "actuated joint, or a joint by the push of a spring or cylinder force element (element "
        '= "NAME"), toward a reference motion table by the computed-torque law (PD gains '
        "kp [1/s²], kd [1/s] or omega, zeta; force_limit, lag or bandwidth, rate_limit, a "
        "cylinder's area); the table gains each one's reference, error, force and flags (a "
        "cylinder element's chamber pressures) "
        "(default: the mechanism file's [[control]] tables; none: the actuated joints are "
        "undriven)",
    )
    simulate.add_argument(
        "--samples",
        action=Once,
        type=int,
        default=SAMPLES,
        metavar="N",
        help=f"output samples over the run, both ends included (default: {SAMPLES}; at most "
        f"{SAMPLE_MEMORY // SAMPLE_BYTES} divided by the mechanism's velocity coordinates: "
        f"{SAMPLE_BYTES / 1e3:g} kB of results per sample and coordinate, "
        f"{SAMPLE_MEMORY / 1e9:g} GB in all)",
    )
    simulate.add_argument(
        "--method",
        action=Once,
        choices=METHODS,
        default="DOP853",
        help="SciPy integrator: explicit DOP853 or RK45, implicit Radau or BDF for stiff "
        "mechanisms (default: DOP853; a run whose explicit steps are held by stiffness, a stiff "
        "damper or spring, gets a warning naming it)",
    )
    simulate.add_argument(
        "--rtol",
        action=Once,
        type=float,
        default=RTOL,
        help=f"relative tolerance of each step (default: {RTOL:g})",
    )
    simulate.add_argument(
        "--atol",
        action=Once,
        type=float,
        default=ATOL,
        help=f"absolute tolerance of each step, rad, m and J (default: {ATOL:g})",
    )
    simulate.add_argument(
        "--rate",
        dest="rates",
        action="append",
        type=rate_argument,
        default=[],
        metavar="JOINT=VALUE",
        help="initial rate of a joint [rad/s revolute, m/s prismatic], repeatable, over the "
        "mechanism file's rates entry of that joint: rates of the independent joints set the "
        "others through the closure; rates of more joints are projected onto it and the summary "
        "says how much they changed (default: the file's rates, or at rest)",
    )
    simulate.add_argument(
        "--singular",
        action=Once,
        choices=MODES,
        default="pass",
        help="at a singular position (the closure Jacobian loses rank: a parallelogram lying "
        "flat): pass through it, listing it in the summary and flagging the samples whose loads "
        "are indeterminate there, or stop there naming the time (default: pass)",
    )
    figures_switch(simulate)


def run(args: argparse.Namespace) -> int:
    """A user's closed-chain mechanism run forward: states.csv, summary, figures."""
    from ..outputs import OutputFolder, write_simulation_outputs
    from ..study.simulate import simulate_mechanism
    from ..viz.mechanism_figures import figure_process

    rates = dict(args.rates)
    if len(rates) < len(args.rates):
        twice = next(name for name, _ in args.rates if [n for n, _ in args.rates].count(name) > 1)
        raise InputError(f"--rate {twice}=… given twice: give each joint's rate once")
    folder = OutputFolder(args.out)
    # The figures' process starts first: it imports matplotlib while this process computes.
    with figure_process(args.figures) as drawing:
        simulation = simulate_mechanism(
            args.closures,
            args.duration,
            model=args.model,
            pose=args.pose,
            forces=args.forces,
            samples=args.samples,
            method=args.method,
            rtol=args.rtol,
            atol=args.atol,
            progress=True,
            rates=rates,
            singular=args.singular,
            control=args.control,
        )
        with folder:
            paths = write_simulation_outputs(
                simulation, folder, command_line(args), figures=args.figures, drawing=drawing
            )
    print(simulation.summary())
    print(wrote(paths, folder.path))
    return 0
