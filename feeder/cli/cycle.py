"""``feeder cycle``: the main study, the dynamics of one cycle cross-checked, with cycle.csv,
the figures and the manifest."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..dynamics.servo import BANDWIDTH_HZ
from ..exceptions import InputError
from .options import (
    FORWARD_MIN_RATE,
    RATE_HELP,
    Once,
    add_command,
    base_of,
    base_options,
    command_line,
    elevation_of,
    params_of,
    study_options,
    switch,
)

if TYPE_CHECKING:
    from ..dynamics.servo import ServoGains


def add(commands: argparse._SubParsersAction) -> None:
    """The ``cycle`` sub-parser."""
    cycle = add_command(commands, "cycle", run, "loads and reactions over a feeding cycle")
    study_options(cycle)
    base_options(cycle)
    cycle.add_argument(
        "--rate",
        action=Once,
        type=float,
        default=1000.0,
        metavar="HZ",
        help=f"{RATE_HELP}; the force-rule forward run needs ≥ {FORWARD_MIN_RATE:g} Hz with the "
        "default stages (below that, add --no-forward); the loads have no minimum",
    )
    switch(
        cycle,
        "--no-forward",
        "forward",
        "skip the forward run and its forward_* or controlled_* columns (default: run it)",
    )
    cycle.add_argument(
        "--forward",
        action=Once,
        dest="forward_kind",
        choices=("force-rule", "controlled"),
        default="force-rule",
        help="the forward run: the paper's force rule (the computed loads applied open loop; "
        "standing or tilted only), or the drives under position control, on any base: the "
        "loading pose against the rammer's line, the settling, the drives' peaks and "
        "saturation (default: %(default)s)",
    )
    cycle.add_argument(
        "--bandwidth",
        action=Once,
        type=float,
        metavar="HZ",
        help=f"the controlled run's position-loop bandwidth [Hz] (default: {BANDWIDTH_HZ:g}, "
        "assumed: docs/REFERENCE.md)",
    )
    cycle.add_argument(
        "--drive-bandwidth",
        action=Once,
        type=float,
        metavar="HZ",
        help="the controlled run's drives as a first-order lag of this bandwidth [Hz], a "
        "servo-valve's (default: ideal drives, no lag)",
    )
    switch(
        cycle,
        "--no-figures",
        "figures",
        "write the table and the manifest only, for batch use (default: every figure)",
    )


def run(args: argparse.Namespace) -> int:
    """The main study: dynamics of one cycle, cross-checked, with cycle.csv and the figures."""
    from ..device.feeder import load_feeder
    from ..motion.laws import CycleSpec
    from ..outputs import OutputFolder, write_cycle_outputs
    from ..study.cycle_study import run_cycle_study
    from ..viz.report import FigureWorkers

    controlled = servo_of(args)
    folder = OutputFolder(args.out)
    params = params_of(args)
    elevation, spec = elevation_of(args, params), CycleSpec(rate=args.rate)
    base = base_of(args)
    # The figure workers start first: they import matplotlib while this process computes.
    with FigureWorkers(None if args.figures else 1) as workers:
        feeder = load_feeder(params)
        with folder:
            study = run_cycle_study(
                feeder,
                elevation,
                spec,
                progress=True,
                forward=args.forward and controlled is None,
                base=base,
                controlled=controlled,
            )
            paths = write_cycle_outputs(
                study, folder, command_line(args), figures=args.figures, workers=workers
            )
    print(f"{feeder.params.name} feeder")
    print(study.summary())
    figures = f" and {len(paths) - 1} figures" if args.figures else ""
    print(f"wrote {paths[0]}{figures} in {folder.path}")
    return 0


def servo_of(args: argparse.Namespace) -> ServoGains | None:
    """The controlled run's position loops from ``--forward controlled``, ``--bandwidth`` and
    ``--drive-bandwidth``; None for the force-rule run or none.

    Raises:
        InputError: ``--forward controlled`` with ``--no-forward``, a bandwidth without
            ``--forward controlled``, a bandwidth that is not a positive number.
    """
    from ..dynamics.servo import ServoGains

    controlled = args.forward_kind == "controlled"
    if controlled and not args.forward:
        raise InputError("--forward controlled and --no-forward contradict: give one")
    given = [
        option
        for option, value in (
            ("--bandwidth", args.bandwidth),
            ("--drive-bandwidth", args.drive_bandwidth),
        )
        if value is not None
    ]
    if given and not controlled:
        raise InputError(f"{' and '.join(given)} set the controlled run: add --forward controlled")
    if not controlled:
        return None
    bandwidth = BANDWIDTH_HZ if args.bandwidth is None else args.bandwidth
    return ServoGains(bandwidth_hz=bandwidth, actuator_hz=args.drive_bandwidth)
