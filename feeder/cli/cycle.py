"""``feeder cycle``: the main study, the dynamics of one cycle cross-checked, with cycle.csv,
the figures and the manifest."""

from __future__ import annotations

import argparse

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
        "skip the force-rule forward run and its forward_* columns (default: run it)",
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

    folder = OutputFolder(args.out)
    params = params_of(args)
    elevation, spec = elevation_of(args, params), CycleSpec(rate=args.rate)
    base = base_of(args)
    # The figure workers start first: they import matplotlib while this process computes.
    with FigureWorkers(None if args.figures else 1) as workers:
        feeder = load_feeder(params)
        with folder:
            study = run_cycle_study(
                feeder, elevation, spec, progress=True, forward=args.forward, base=base
            )
            paths = write_cycle_outputs(
                study, folder, command_line(args), figures=args.figures, workers=workers
            )
    print(f"{feeder.params.name} feeder")
    print(study.summary())
    figures = f" and {len(paths) - 1} figures" if args.figures else ""
    print(f"wrote {paths[0]}{figures} in {folder.path}")
    return 0
