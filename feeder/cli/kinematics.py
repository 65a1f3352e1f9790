"""``feeder kinematics``: the kinematics of one cycle, cycle.csv (kinematic columns), Figs. 4
and 10."""

from __future__ import annotations

import argparse

from .options import (
    RATE_HELP,
    Once,
    add_command,
    command_line,
    elevation_of,
    params_of,
    study_options,
    switch,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``kinematics`` sub-parser."""
    kinematics = add_command(commands, "kinematics", run, "kinematics of the feeding cycle")
    study_options(kinematics)
    kinematics.add_argument(
        "--rate", action=Once, type=float, default=1000.0, metavar="HZ", help=RATE_HELP
    )
    switch(
        kinematics,
        "--no-figures",
        "figures",
        "write the table and the manifest only, for batch use (default: Figs. 4 and 10)",
    )


def run(args: argparse.Namespace) -> int:
    """Kinematics of one cycle: cycle.csv, Fig. 4 (workspace), Fig. 10 (position), summary."""
    from ..device.feeder import load_feeder
    from ..motion.cycle import feeding_cycle
    from ..motion.laws import CycleSpec
    from ..outputs import OutputFolder, write_kinematics_outputs
    from ..study.summary import kinematics_summary

    folder = OutputFolder(args.out)
    params = params_of(args)
    elevation, spec = elevation_of(args, params), CycleSpec(rate=args.rate)
    feeder = load_feeder(params)
    with folder:
        cycle = feeding_cycle(feeder, elevation, spec)
        paths = write_kinematics_outputs(
            feeder, cycle, folder, command_line(args), figures=args.figures
        )
    print(kinematics_summary(feeder, cycle))
    figures = f"{len(paths) - 1} figures" if args.figures else "no figures (--no-figures)"
    print(f"wrote {paths[0]} and {figures} in {folder.path}")
    return 0
