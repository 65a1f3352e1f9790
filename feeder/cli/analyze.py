"""``feeder analyze``: a user's closed-chain mechanism, its mobility report (``--check``), or
its motion's loads and every reaction (``--motion``, ``--out``)."""

from __future__ import annotations

import argparse

from ..exceptions import InputError, SingularPoseError
from .options import (
    Once,
    add_command,
    command_line,
    figures_switch,
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
        help="motion table (CSV: t and q_<joint> of the independent joints): required, and "
        "refused with --check (default: none)",
    )
    analyze.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        metavar="DIR",
        help="output folder for loads.csv, summary.txt and the figures: required, and refused "
        "with --check (default: none)",
    )
    figures_switch(analyze)
    switch(
        analyze,
        "--check",
        "check",
        "print the mobility report and the assembled pose instead; exit status 0 when the "
        "independent joints drive the mechanism there, 2 when they cannot (then analyze would "
        "fail too) or on bad input (default: off)",
    )


def run(args: argparse.Namespace) -> int:
    """A user's closed-chain mechanism: its mobility report (``--check``), or its motion's
    loads and every reaction (``--motion``, ``--out``)."""
    from ..study.analyze import analyze, check_mechanism

    if args.check:
        given = [
            name
            for name, value in (
                ("--motion", args.motion),
                ("--out", args.out),
                ("--no-figures", not args.figures),
            )
            if value
        ]
        if given:  # they would be ignored: the report is printed, nothing is computed or written
            raise InputError(
                f"--check prints the mobility report only: leave out {', '.join(given)}"
            )
        check = check_mechanism(args.closures, args.model, args.pose)
        print(check.text)
        if not check.drives:
            raise SingularPoseError(
                f"the independent joints {list(check.report.independent)} cannot drive the "
                "mechanism at its assembled pose (the report above says why): feeder analyze "
                "would refuse the motion; if that pose is not the assembly you mean (a singular "
                "one: a collapsed or folded branch), mount from one nearer it with --pose FILE "
                "(joint,value rows) or a TOML file's pose = {...}"
            )
        return 0
    if args.motion is None or args.out is None:
        raise InputError("give --motion FILE and --out DIR (or --check for the mobility report)")
    from ..outputs import OutputFolder, write_analysis_outputs
    from ..viz.mechanism_figures import figure_process

    folder = OutputFolder(args.out)
    # The figures' process starts first: it imports matplotlib while this process computes.
    with figure_process(args.figures) as drawing:
        analysis = analyze(args.closures, args.motion, args.model, args.pose)
        with folder:
            paths = write_analysis_outputs(
                analysis, folder, command_line(args), figures=args.figures, drawing=drawing
            )
    print(analysis.summary())
    print(wrote(paths, folder.path))
    return 0
