"""Command line: ``feeder <command> ...`` (also ``python -m feeder``). Parse, call, print.

Commands:
    cycle       the main study: loads and reactions of a cycle, cycle.csv and Figs. 4, 8, 10–15
    kinematics  the cycle's kinematics only: cycle.csv (kinematic columns), Figs. 4 and 10
    parameters  every number of the built-in devices with its unit and source (Markdown)
    urdf        regenerate the shipped URDF files from the parameter sets
    errata      the table of the paper's errata measured on the reference cycle (Markdown)
    view        MeshCat viewer of the cycle on 127.0.0.1, or a static HTML page of it
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from .device.builtin import DEVICES
from .exceptions import FeederError
from .validation import check_number


def _elevation(args: argparse.Namespace) -> float:
    """The ``--elevation`` option [deg] in radians."""
    return math.radians(check_number("elevation [deg]", args.elevation))


def _write_or_print(text: str, out: str | None) -> None:
    from .files import write_text

    if out is None:
        print(text, end="")
    else:
        print(f"wrote {write_text(out, text)}")


def cmd_parameters(args: argparse.Namespace) -> int:
    """Print the parameter table, or write it to a file."""
    from .device.table import parameters_markdown

    _write_or_print(parameters_markdown(), args.out)
    return 0


def cmd_errata(args: argparse.Namespace) -> int:
    """Print the errata table, or write it to a file."""
    from .study.errata import paper_errata

    _write_or_print(paper_errata(), args.out)
    return 0


def cmd_urdf(args: argparse.Namespace) -> int:
    """Write the built-in devices' URDF files."""
    from .device.urdf_writer import write_urdfs

    for path in write_urdfs(args.out):
        print(f"wrote {path}")
    return 0


def cmd_kinematics(args: argparse.Namespace) -> int:
    """Kinematics of one cycle: cycle.csv, Fig. 4 (workspace), Fig. 10 (position), summary."""
    from .device.feeder import load_feeder
    from .motion.cycle import feeding_cycle
    from .motion.laws import CycleSpec
    from .outputs import output_folder, write_kinematics_outputs
    from .study.summary import kinematics_summary

    out = output_folder(args.out)
    feeder = load_feeder(args.device)
    cycle = feeding_cycle(feeder, _elevation(args), CycleSpec(rate=args.rate))
    paths = write_kinematics_outputs(feeder, cycle, out)
    print(kinematics_summary(feeder, cycle))
    print(f"wrote {paths[0]} and figures in {out}")
    return 0


def cmd_cycle(args: argparse.Namespace) -> int:
    """The main study: dynamics of one cycle, cross-checked, with cycle.csv and the figures."""
    from .device.feeder import load_feeder
    from .motion.laws import CycleSpec
    from .outputs import output_folder, write_cycle_outputs
    from .study.cycle_study import run_cycle_study

    out = output_folder(args.out)
    feeder = load_feeder(args.device)
    study = run_cycle_study(
        feeder, _elevation(args), CycleSpec(rate=args.rate), progress=True, forward=args.forward
    )
    paths = write_cycle_outputs(study, out)
    print(f"{feeder.params.name} feeder")
    print(study.summary())
    print(f"wrote {paths[0]} and {len(paths) - 1} figures in {out}")
    return 0


def cmd_view(args: argparse.Namespace) -> int:
    """Animate the cycle in MeshCat (127.0.0.1 only) or write it as a static HTML page."""
    from .device.feeder import load_feeder
    from .dynamics.cycle import cycle_dynamics
    from .viz.viewer import check_port, check_writable, cycle_forces, show_cycle, write_html

    feeder = load_feeder(args.device)
    elevation = _elevation(args)
    html = None if args.html is None else check_writable(args.html)
    port = check_port(args.port)
    dynamics = cycle_dynamics(feeder, elevation, forward=False)
    cycle, forces = dynamics.kinematics, cycle_forces(feeder, dynamics)
    if html is not None:
        print(f"wrote {write_html(feeder, cycle, html, forces, port=port)}")
        return 0
    with show_cycle(feeder, cycle, forces, port=port) as viewer:
        print(f"{feeder.params.name} feeder at {args.elevation:g}°: open {viewer.url}")
        print("press Ctrl-C to stop the viewer")
        viewer.serve_forever()
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="feeder", description="Analysis of the 152 mm SPH M77 ammunition feeding device."
    )
    commands = parser.add_subparsers(dest="command", required=True)

    parameters = commands.add_parser("parameters", help="the parameter table with sources")
    parameters.add_argument("--out", help="Markdown file to write (default: print)")
    parameters.set_defaults(run=cmd_parameters)

    errata = commands.add_parser("errata", help="the paper's errata on the reference cycle")
    errata.add_argument("--out", help="Markdown file to write (default: print)")
    errata.set_defaults(run=cmd_errata)

    urdf = commands.add_parser("urdf", help="regenerate the URDF files from the parameters")
    urdf.add_argument("--out", default="urdf", help="folder to write into (default: urdf)")
    urdf.set_defaults(run=cmd_urdf)

    def cycle_options(sub: argparse.ArgumentParser) -> None:
        sub.add_argument(
            "--elevation", type=float, required=True, help="barrel elevation ε [deg], −4 … 70"
        )
        sub.add_argument("--out", required=True, help="output folder")
        sub.add_argument("--device", choices=sorted(DEVICES), default="projectile")
        sub.add_argument("--rate", type=float, default=1000.0, help="sample rate [Hz]")

    cycle = commands.add_parser("cycle", help="loads and reactions over a feeding cycle")
    cycle_options(cycle)
    cycle.add_argument(
        "--no-forward",
        dest="forward",
        action="store_false",
        help="skip the force-rule forward run (and its forward_* columns)",
    )
    cycle.set_defaults(run=cmd_cycle)

    kinematics = commands.add_parser("kinematics", help="kinematics of the feeding cycle")
    cycle_options(kinematics)
    kinematics.set_defaults(run=cmd_kinematics)

    view = commands.add_parser("view", help="animate the cycle in the browser (MeshCat)")
    view.add_argument("--elevation", type=float, required=True, help="barrel elevation ε [deg]")
    view.add_argument("--device", choices=sorted(DEVICES), default="projectile")
    view.add_argument("--html", help="write a self-contained HTML page to this file instead")
    view.add_argument("--port", type=int, help="web port on 127.0.0.1 (default: a free one)")
    view.set_defaults(run=cmd_view)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (2 for bad input)."""
    args = _parser().parse_args(argv)
    try:
        return args.run(args)
    except FeederError as exc:
        print(f"feeder: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
