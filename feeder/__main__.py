"""Command line: ``feeder <command> ...`` (also ``python -m feeder``).

Commands:
    cycle       the main study: loads and reactions of a cycle, cycle.csv and Figs. 4, 8, 10–15
    kinematics  the cycle's kinematics only: cycle.csv (kinematic columns), Figs. 4 and 10
    parameters  every number of the built-in devices with its unit and source (Markdown)
    urdf        regenerate the shipped URDF files from the parameter sets
    view        MeshCat viewer of the cycle on 127.0.0.1, or a static HTML page of it
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

from .exceptions import FeederError, InputError, check_finite
from .parameters import DEVICES


def _elevation(args: argparse.Namespace) -> float:
    return math.radians(float(check_finite("elevation [deg]", args.elevation)))


def _output_dir(path: str) -> Path:
    """Create the output folder now, so that a bad path fails before any computation."""
    directory = Path(path)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the output folder {directory}: {exc}") from exc
    return directory


def cmd_parameters(args: argparse.Namespace) -> int:
    """Print the parameter table, or write it to a file."""
    from .parameters import parameters_markdown

    text = parameters_markdown()
    if args.out is None:
        print(text, end="")
    else:
        try:
            Path(args.out).write_text(text, encoding="utf-8")
        except OSError as exc:
            raise InputError(f"cannot write {args.out}: {exc}") from exc
        print(f"wrote {args.out}")
    return 0


def cmd_urdf(args: argparse.Namespace) -> int:
    """Write the built-in devices' URDF files."""
    from .urdf import write_urdfs

    for path in write_urdfs(args.out):
        print(f"wrote {path}")
    return 0


def cmd_kinematics(args: argparse.Namespace) -> int:
    """Kinematics of one cycle: cycle.csv, Fig. 4 (workspace), Fig. 10 (position), summary."""
    import numpy as np

    from .cycle import CycleSpec, feeding_cycle
    from .device import load_feeder
    from .kinematics import arm_travel, required_stroke
    from .plots import plot_position, plot_workspace
    from .results import write_csv
    from .workspace import workspace

    out = _output_dir(args.out)
    feeder = load_feeder(args.device)
    elevation = _elevation(args)
    cycle = feeding_cycle(feeder, elevation, CycleSpec(rate=args.rate))
    write_csv(out / "cycle.csv", cycle.columns())
    low, high = feeder.params.elevation_limits
    space = workspace(feeder, np.radians(np.arange(math.degrees(low), math.degrees(high) + 1, 10)))
    plot_workspace(out / "fig04_workspace.png", space, feeder.params.name)
    plot_position(out / "fig10_projectile_position.png", cycle)
    speed = np.linalg.norm(cycle.projectile_velocity, axis=1)
    k = int(np.argmax(speed))
    print(f"{feeder.params.name} feeder, elevation {args.elevation:g}°")
    print(f"  piston stroke needed over the range: {required_stroke(feeder.params) * 1e3:.1f} mm")
    print(f"  piston travel this cycle: {(cycle.q[-1, 1] - cycle.q[0, 1]) * 1e3:.1f} mm")
    print(f"  arm travel: {math.degrees(arm_travel(elevation)):.1f}°")
    print(f"  peak payload speed: {speed[k]:.3f} m/s at t = {cycle.t[k]:.3f} s")
    print(
        f"  transmission angle: {np.degrees(cycle.transmission_angle.min()):.1f}° … "
        f"{np.degrees(cycle.transmission_angle.max()):.1f}°"
    )
    print(f"  max closure residual: {cycle.closure_residual.max():.2e} m")
    print(f"wrote {out / 'cycle.csv'} and figures in {out}")
    return 0


def cmd_cycle(args: argparse.Namespace) -> int:
    """The main study: dynamics of one cycle, cross-checked, with cycle.csv and the figures."""
    from .cycle import CycleSpec
    from .device import load_feeder
    from .study import run_cycle_study, write_cycle_study

    out = _output_dir(args.out)
    feeder = load_feeder(args.device)
    study = run_cycle_study(
        feeder, _elevation(args), CycleSpec(rate=args.rate), progress=True, forward=args.forward
    )
    paths = write_cycle_study(study, feeder, out)
    print(f"{feeder.params.name} feeder")
    print(study.summary())
    print(f"wrote {paths[0]} and {len(paths) - 1} figures in {out}")
    return 0


def cmd_view(args: argparse.Namespace) -> int:
    """Animate the cycle in MeshCat (127.0.0.1 only) or write it as a static HTML page."""
    from .viewer import view_command

    return view_command(args.device, args.elevation, args.html, args.port)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="feeder", description="Analysis of the 152 mm SPH M77 ammunition feeding device."
    )
    commands = parser.add_subparsers(dest="command", required=True)

    parameters = commands.add_parser("parameters", help="the parameter table with sources")
    parameters.add_argument("--out", help="Markdown file to write (default: print)")
    parameters.set_defaults(run=cmd_parameters)

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
