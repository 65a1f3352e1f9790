"""``feeder sweep``: peak loads over elevations × parameter variants × devices, resumable."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..device.builtin import DEVICES
from .options import (
    Once,
    add_command,
    command_line,
    elevations_option,
    parallel_options,
    path_argument,
    switch,
    typed,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``sweep`` sub-parser."""
    from ..study.grid import DEFAULT_ELEVATIONS_DEG

    sweep = add_command(commands, "sweep", run, "peak loads over elevations × variants × devices")
    sweep.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        required=True,
        metavar="DIR",
        help="output folder, required: new, empty, or one an earlier feeder run wrote (the "
        "manifest feeder-run.json records the run); a sweep already there is resumed, the "
        "outputs of another run are replaced",
    )
    sweep.add_argument(
        "--grid",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="grid file (TOML): devices, elevations, rate, variants (default: the projectile "
        "feeder at every degree of −4 … 70)",
    )
    sweep.add_argument(
        "--device",
        action="append",
        choices=sorted(DEVICES),
        help="built-in device, replacing the grid's (repeatable; default: the grid's)",
    )
    elevations_option(sweep, f"the grid's, else {typed(DEFAULT_ELEVATIONS_DEG)}")
    parallel_options(sweep, "the cases")
    switch(
        sweep,
        "--parquet",
        "parquet",
        "also write sweep_peaks.parquet (pip install 'feeder[parquet]'; default: CSV only)",
    )
    switch(
        sweep,
        "--no-figures",
        "figures",
        "the table only (default: one figure of peaks against elevation per device)",
    )


def run(args: argparse.Namespace) -> int:
    """Peak loads over elevations × parameter variants × devices; resumable."""
    import contextlib
    from functools import partial

    from ..study.grid import elevation_range
    from ..study.sweep_folder import run_sweep
    from ..viz.png import write_png
    from ..viz.report import SweepFigures

    def figures(table: Path) -> dict[str, partial]:
        return {name: partial(write_png, png=png) for name, png in drawing.pngs(table).items()}

    elevations = None if args.elevations is None else elevation_range(*args.elevations)
    # the figures' process first, forked while this one runs a single thread: it imports
    # matplotlib while the cases compute
    with SweepFigures() if args.figures else contextlib.nullcontext() as drawing:
        outputs = run_sweep(
            args.grid,
            args.out,
            devices=args.device,
            elevations=elevations,
            scheduler=args.scheduler,
            workers=args.workers,
            progress=True,
            parquet=args.parquet,
            figures=figures if args.figures else None,
            command=command_line(args),
        )
    print(outputs.summary())
    count = sum(path.suffix == ".png" for path in outputs.files)
    drawn = f" and {count} figure{'' if count == 1 else 's'}" if count else ""
    print(f"wrote {outputs.table.name}{drawn} in {outputs.table.parent}")
    return 0
