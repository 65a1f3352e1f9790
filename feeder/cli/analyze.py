"""``feeder analyze``: a user's closed-chain mechanism, its mobility report (``--check``), or
its motion's loads and every reaction (``--motion``, ``--out``)."""

from __future__ import annotations

import argparse

from ..exceptions import InputError
from .options import (
    Once,
    add_command,
    command_line,
    mechanism_options,
    path_argument,
    switch,
    wrote,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``analyze`` sub-parser."""
    analyze = add_command(
        commands, "analyze", run, "any closed-chain mechanism: mobility, loads, every reaction"
    )
    mechanism_options(analyze)
    analyze.add_argument(
        "--motion",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="motion table (CSV: t and q_<joint> of the independent joints), required "
        "unless --check (default: none)",
    )
    analyze.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        metavar="DIR",
        help="output folder for loads.csv, summary.txt and the figures, required unless "
        "--check (default: none)",
    )
    switch(
        analyze,
        "--check",
        "check",
        "print the mobility report and the assembled pose instead (default: off)",
    )


def run(args: argparse.Namespace) -> int:
    """A user's closed-chain mechanism: its mobility report (``--check``), or its motion's
    loads and every reaction (``--motion``, ``--out``)."""
    from ..study.analyze import analyze, check_mechanism

    if args.check:
        print(check_mechanism(args.closures, args.model, args.pose))
        return 0
    if args.motion is None or args.out is None:
        raise InputError("give --motion FILE and --out DIR (or --check for the mobility report)")
    from ..outputs import OutputFolder, write_analysis_outputs

    folder = OutputFolder(args.out)
    analysis = analyze(args.closures, args.motion, args.model, args.pose)
    with folder:
        paths = write_analysis_outputs(analysis, folder, command_line(args))
    print(analysis.summary())
    print(wrote(paths, folder.path))
    return 0
