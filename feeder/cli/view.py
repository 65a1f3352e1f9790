"""``feeder view``: the cycle (on a vehicle with ``--slope`` / ``--base-motion``), or a user's
mechanism (MODEL ``--closures F``, its vehicle from the file's ``[base]``), in MeshCat on
127.0.0.1 only, or as a static HTML page (``--html FILE``)."""

from __future__ import annotations

import argparse
from contextlib import suppress
from pathlib import Path
from typing import TYPE_CHECKING

from ..exceptions import InputError
from .options import (
    Once,
    add_command,
    base_of,
    base_options,
    elevation_of,
    mechanism_options,
    params_of,
    path_argument,
    study_options,
)

if TYPE_CHECKING:  # MeshCat is imported by the subcommand that draws
    from ..viz.scene import MechanismScene


def add(commands: argparse._SubParsersAction) -> None:
    """The ``view`` sub-parser."""
    view = add_command(
        commands,
        "view",
        run,
        "animate the cycle, or any mechanism (MODEL --closures F), in the browser (MeshCat, "
        "127.0.0.1)",
    )
    study_options(view, out=False, required=False)
    base_options(view)
    mechanism_options(view, required=False)
    source = view.add_mutually_exclusive_group()
    source.add_argument(
        "--motion",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="a mechanism's motion table, analysed as feeder analyze does (default: the "
        "assembled pose with its static loads)",
    )
    source.add_argument(
        "--run",
        dest="run_dir",
        action=Once,
        type=path_argument,
        metavar="DIR",
        help="the output folder of an earlier feeder analyze or feeder simulate of the "
        "mechanism (default: none)",
    )
    view.add_argument(
        "--reactions",
        action=Once,
        nargs="+",
        metavar="JOINT",
        help="joints whose reaction force is drawn (default: the few of largest peak force)",
    )
    view.add_argument(
        "--html",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="write a self-contained HTML page (opens offline) instead of serving: a new file, "
        "or a page that feeder view wrote (replaced); any other existing file is refused "
        "(default: serve until Ctrl-C)",
    )
    view.add_argument(
        "--port",
        action=Once,
        type=int,
        help="web port on 127.0.0.1 of the live viewer (default: a free one); not with --html",
    )


def run(args: argparse.Namespace) -> int:
    """Animate the cycle or a mechanism in MeshCat (127.0.0.1 only) or write it as a static
    HTML page."""
    from ..viz.viewer import check_port, check_writable

    html = None if args.html is None else check_writable(args.html)
    port = check_port(args.port)
    if html is not None and port is not None:
        raise InputError("--port is the live viewer's; --html writes the page without a server")
    if args.model is None:
        return _view_device(args, html, port)
    device = [flag for flag, value in (("--elevation", args.elevation), ("--device",
              args.device), ("--params", args.params), ("--slope", args.slope), ("--base-motion",
              args.base_motion)) if value is not None]  # fmt: skip
    if device:
        moving = args.slope is not None or args.base_motion is not None
        hint = " (a MODEL's base motion is its file's [base])" if moving else ""
        raise InputError(
            f"{', '.join(device)}: options of the device's view, not of a MODEL's{hint}"
        )
    if args.closures is None:
        raise InputError("give --closures FILE with MODEL (the mechanism file)")
    from ..study.view import motion_view, pose_view, run_view
    from ..viz.model_scene import model_scene

    if args.motion is not None:
        view = motion_view(args.closures, args.motion, args.model, args.pose)
    elif args.run_dir is not None:
        view = run_view(args.closures, args.run_dir, args.model, args.pose)
    else:
        view = pose_view(args.closures, args.model, args.pose)
    scene = model_scene(view, args.reactions)
    return _write_or_serve(scene, html, port, f"{args.model.name} ({view.source})")


def _view_device(args: argparse.Namespace, html: Path | None, port: int | None) -> int:
    """``feeder view --elevation DEG``: the device's cycle."""
    from ..device.feeder import load_feeder
    from ..dynamics.cycle import cycle_dynamics
    from ..viz.device_scene import cycle_forces, device_scene

    mechanism = [flag for flag, value in (("--closures", args.closures), ("--pose", args.pose),
                 ("--motion", args.motion), ("--run", args.run_dir), ("--reactions",
                 args.reactions)) if value is not None]  # fmt: skip
    if mechanism:
        raise InputError(f"{', '.join(mechanism)}: options of a MODEL's view; give MODEL")
    if args.elevation is None:
        raise InputError("give --elevation DEG for the device's view (or MODEL --closures F)")
    params = params_of(args)
    elevation = elevation_of(args, params)
    base = base_of(args)
    feeder = load_feeder(params)
    dynamics = cycle_dynamics(feeder, elevation, base=base, forward=False)
    scene = device_scene(feeder, dynamics.kinematics, cycle_forces(feeder, dynamics), base=base)
    where = "" if base is None else f" ({base.describe()})"
    return _write_or_serve(
        scene, html, port, f"{feeder.params.name} feeder at {args.elevation:g}°{where}"
    )


def _write_or_serve(scene: MechanismScene, html: Path | None, port: int | None, what: str) -> int:
    """Write the scene's page to ``html`` or, without it, serve the scene until Ctrl-C (the
    first line printed says what is shown, ``what``, and where)."""
    from ..viz.viewer import show, write_html

    if html is not None:
        print(f"wrote {write_html(scene, html)}")
        return 0
    # Ctrl-C is how the viewer stops: from the first line printed on, it ends with status 0.
    with show(scene, port=port) as viewer, suppress(KeyboardInterrupt):
        print(f"{what}: open {viewer.url}")
        print("press Ctrl-C to stop the viewer", flush=True)
        viewer.serve_forever()
    return 0
