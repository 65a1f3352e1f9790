"""``feeder errata``: the table of the paper's errata measured on the reference cycle."""

from __future__ import annotations

import argparse

from .options import (
    Once,
    add_command,
    device_options,
    params_of,
    path_argument,
    write_or_print,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``errata`` sub-parser."""
    errata = add_command(commands, "errata", run, "the paper's errata on the reference cycle")
    errata.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="file to write: a new file, or an errata table that feeder errata wrote (replaced); "
        "any other existing file is refused (default: print)",
    )
    device_options(errata, "projectile")


def run(args: argparse.Namespace) -> int:
    """Print the errata table, or write it: to a new file, or over a table that this command
    wrote (checked before the table is computed)."""
    from ..files import check_replaceable
    from ..paper.errata import ERRATA_MARKER
    from ..study.errata import paper_errata

    if args.out is not None:
        check_replaceable(args.out, "an errata table that feeder errata wrote", ERRATA_MARKER)

    device = (
        params_of(args) if args.params is not None or args.device is not None else "projectile"
    )
    write_or_print(paper_errata(device), args.out)
    return 0
