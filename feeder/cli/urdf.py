"""``feeder urdf``: regenerate the URDF files from the parameter sets."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..exceptions import InputError
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
        help="folder to write <device>_feeder.urdf into (default: %(default)s)",
    )
    device_options(urdf, "every built-in device")


def run(args: argparse.Namespace) -> int:
    """Write the URDF file of the given parameter set, or of every built-in device."""
    from ..device.urdf_writer import urdf_string, write_urdfs
    from ..files import path_in, write_text

    if args.params is None and args.device is None:
        paths = write_urdfs(args.out)
    else:
        params = params_of(args)
        text = urdf_string(params)
        path = path_in(args.out, f"{params.name}_feeder.urdf", "the URDF file")
        try:
            args.out.mkdir(parents=True, exist_ok=True)  # as write_urdfs does
        except OSError as exc:
            raise InputError(f"cannot write the URDF file into {args.out}: {exc}") from exc
        paths = [write_text(path, text)]
    for path in paths:
        print(f"wrote {path}")
    return 0
