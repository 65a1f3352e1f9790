"""``feeder urdf``: regenerate the URDF files from the parameter sets."""

from __future__ import annotations

import argparse
from pathlib import Path

from .options import (
    Once,
    add_command,
    device_options,
    params_of,
    path_argument,
)


def add(commands: argparse._SubParsersAction) -> None:
    """The ``urdf`` sub-parser."""
    urdf = add_command(commands, "urdf", run, "regenerate the URDF files from the parameters")
    urdf.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        default=Path("urdf"),
        metavar="DIR",
        help="folder to write <device>_feeder.urdf into: a new file, or over one that feeder urdf "
        "wrote; any other file of that name is refused (default: %(default)s)",
    )
    device_options(urdf, "every built-in device")


def run(args: argparse.Namespace) -> int:
    """Write the URDF file of the given parameter set, or of every built-in device: new files,
    or over URDF files that feeder wrote (never over a user's file)."""
    from ..device.urdf_writer import write_urdfs

    devices = None if args.params is None and args.device is None else [params_of(args)]
    for path in write_urdfs(args.out, devices):
        print(f"wrote {path}")
    return 0
