"""``feeder design``: designing the device's geometry. ``feeder design sensitivities``: the
derivative of every peak load with respect to every length and mass, at one elevation and as
the envelope over an elevation range."""

from __future__ import annotations

import argparse

from .options import Once, add_command, command_line, device_options, path_argument, switch


def add(commands: argparse._SubParsersAction) -> None:
    """The ``design`` sub-parser and its own sub-commands."""
    about = "designing the geometry: sensitivities of the peaks"
    design = commands.add_parser("design", help=about, description=about, allow_abbrev=False)
    tasks = design.add_subparsers(dest="design_command", required=True, metavar="TASK")
    sensitivities = add_command(
        tasks,
        "sensitivities",
        run,
        "derivatives and elasticities of every peak load with respect to every length and mass",
    )
    sensitivities.add_argument(
        "--elevations",
        action=Once,
        nargs=3,
        type=float,
        metavar=("START", "STOP", "STEP"),
        help="the envelope's elevations [deg], STOP included when on a step (default: none; "
        "give this, --elevation, or both)",
    )
    sensitivities.add_argument(
        "--elevation",
        action=Once,
        type=float,
        metavar="DEG",
        help="one elevation ε [deg] to differentiate the peaks at (default: none)",
    )
    sensitivities.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        required=True,
        metavar="DIR",
        help="output folder, required: new, empty, or one an earlier feeder run wrote (its "
        "outputs are replaced; the manifest feeder-run.json records the run)",
    )
    device_options(sensitivities, "projectile")
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
        help="relative finite-difference step, in (0, 0.1] (default: ε^(1/3) = 6.06e-6 of "
        "max(|p|, 0.1 m or 1 kg), checked by halving)",
    )
    sensitivities.add_argument(
        "--rate",
        action=Once,
        type=float,
        default=1000.0,
        metavar="HZ",
        help="sample rate of every cycle [Hz] (default: %(default)g)",
    )
    sensitivities.add_argument(
        "--workers",
        action=Once,
        type=int,
        help="local processes (default: every core; 1: this process)",
    )
    sensitivities.add_argument(
        "--scheduler",
        action=Once,
        metavar="tcp://HOST:PORT",
        help="run the cycles on this Dask cluster (pip install 'feeder[cluster]'; default: "
        "this machine)",
    )
    switch(
        sensitivities,
        "--no-figures",
        "figures",
        "the tables and the summary only (default: also sensitivities.png)",
    )


def run(args: argparse.Namespace) -> int:
    """Sensitivities of every peak; the tables, the summary, the figure and the manifest."""
    from ..design.differences import STEP_FACTOR
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
        spec=CycleSpec(rate=args.rate),
        factor=STEP_FACTOR if args.step is None else args.step,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=True,
        figure=args.figures,
        command=command_line(args),
    )
    print(summary(result))
    names = ", ".join(path.name for path in paths)
    print(f"wrote {names} in {paths[0].parent}")
    return 0
