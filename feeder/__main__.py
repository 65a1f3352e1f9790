"""Command line: ``feeder <command> ...`` (also ``python -m feeder``). Parse, check, call, print.

Commands:
    cycle       the main study: loads and reactions of a cycle, cycle.csv and Figs. 4, 8, 10–15
    kinematics  the cycle's kinematics only: cycle.csv (kinematic columns), Figs. 4 and 10
    view        MeshCat viewer of the cycle, or of any mechanism (MODEL --closures F), on
                127.0.0.1, or a static HTML page of it
    parameters  every number of a device with its unit and source (Markdown), or its parameter
                file (TOML, ``--format toml``)
    urdf        regenerate the URDF files from the parameter sets
    errata      the table of the paper's errata measured on the reference cycle (Markdown)
    sweep       peak loads over elevations × parameter variants × devices, resumable
    analyze     any closed-chain mechanism: mobility report, or its loads and every reaction
    simulate    any closed-chain mechanism run forward from rest under gravity and its force
                elements: states, loads, reactions, drift and energy balance

A command is a function ``cmd_<name>(args) -> int`` and a sub-parser in :func:`_parser`, built
from the shared option groups (:func:`_device_options`, :func:`_study_options`), so that every
command spells ``--device``, ``--params``, ``--elevation`` and ``--out`` alike. Each command
checks all its input before it creates a file or a folder. Every option may be given once.
Bad input exits with status 2 and one line that names it; Ctrl-C exits with status 130 and one
line, and leaves no file half-written (:mod:`feeder.outputs`).
"""

from __future__ import annotations

import argparse
import difflib
import math
import shlex
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from contextlib import suppress
from pathlib import Path
from typing import TYPE_CHECKING

from .device.builtin import DEVICES
from .exceptions import FeederError, FeederWarning, InputError
from .validation import check_elevation, check_number, check_path

if TYPE_CHECKING:
    from .device.parameters import FeederParameters

FORWARD_MIN_RATE = 500.0
"""Lowest sample rate [Hz] at which the force-rule forward run tracks the default stages within
its 1e-4 rad check (3.8e-5 rad at 500 Hz, 1.2e-4 rad at 400 Hz: the table in
:mod:`feeder.dynamics.cycle`). Stated in ``feeder cycle --help``."""

INTERRUPTED = 130
"""Exit status after Ctrl-C (SIGINT): 128 + the signal's number, as shells report it."""

TERMINATED = 128 + signal.SIGTERM
"""Exit status after SIGTERM (``kill``, a job scheduler's stop): 143, as shells report it."""


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is, so that it stops as after Ctrl-C: worker pools
    shut down, half-written outputs removed (a KeyboardInterrupt for every cleanup path)."""


def _terminate(signum, frame) -> None:
    raise _Terminated


class _Once(argparse.Action):
    """Store an option's value, or its constant for a flag (``nargs=0``); a second occurrence
    is an error (argparse would silently keep the last: ``--elevation 10 --elevation 20``)."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", set())
        if self.dest in given:
            parser.error(f"{'/'.join(self.option_strings)} given twice: give it once")
        given.add(self.dest)
        setattr(namespace, self.dest, self.const if self.nargs == 0 else values)


def _path(text: str) -> Path:
    """An argument naming a file or folder (:func:`~feeder.validation.check_path`)."""
    try:
        return check_path("the path", text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def _params(args: argparse.Namespace) -> FeederParameters:
    """The parameter set of ``--params FILE`` (read and checked) or of ``--device NAME``."""
    if args.params is not None:
        from .device.parameter_file import read_parameters

        return read_parameters(args.params)
    return DEVICES[args.device or "projectile"]


def _elevation(args: argparse.Namespace, params: FeederParameters) -> float:
    """The ``--elevation`` option [deg] in radians, checked against the device's range."""
    degrees = check_number("elevation [deg]", args.elevation)
    return check_elevation(math.radians(degrees), params.elevation_limits)


def _command(args: argparse.Namespace) -> str:
    """The command line as typed, for the output folder's manifest."""
    return shlex.join(["feeder", *args.argv])


def _write_or_print(text: str, out: Path | None) -> None:
    from .files import write_text

    if out is None:
        print(text, end="")
    else:
        print(f"wrote {write_text(out, text)}")


def cmd_parameters(args: argparse.Namespace) -> int:
    """Print the parameter table (Markdown) or a parameter file (TOML), or write it: to a new
    file, or over a Markdown table that this command wrote (never over an edited parameter file
    or any other file)."""
    from .device.parameter_file import parameters_toml
    from .device.table import parameters_markdown

    if args.format == "toml":
        text = parameters_toml(_params(args))
    elif args.params is not None:
        params = _params(args)
        text = parameters_markdown({params.name: params}, origin=str(args.params))
    elif args.device is not None:
        text = parameters_markdown({args.device: DEVICES[args.device]})
    else:
        text = parameters_markdown()
    if args.out is not None and args.out.exists():
        head = ["", "", ""]  # unreadable (a folder, not text): not a table
        with suppress(OSError, UnicodeDecodeError), args.out.open(encoding="utf-8") as handle:
            head = [handle.readline() for _ in range(3)]  # a table: heading, blank, origin
        if not (
            head[0].startswith("# Parameters")
            and head[2].startswith(("Generated by `feeder parameters", "Read from the parameter"))
        ):
            raise InputError(
                f"{args.out} exists and is not a parameter table that feeder parameters wrote: "
                "choose a new file, or move it away first"
            )
    _write_or_print(text, args.out)
    return 0


def cmd_errata(args: argparse.Namespace) -> int:
    """Print the errata table, or write it to a file."""
    from .study.errata import paper_errata

    device = _params(args) if args.params is not None or args.device is not None else "projectile"
    _write_or_print(paper_errata(device), args.out)
    return 0


def cmd_urdf(args: argparse.Namespace) -> int:
    """Write the URDF file of the given parameter set, or of every built-in device."""
    from .device.urdf_writer import urdf_string, write_urdfs
    from .files import path_in, write_text

    if args.params is None and args.device is None:
        paths = write_urdfs(args.out)
    else:
        params = _params(args)
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


def cmd_kinematics(args: argparse.Namespace) -> int:
    """Kinematics of one cycle: cycle.csv, Fig. 4 (workspace), Fig. 10 (position), summary."""
    from .device.feeder import load_feeder
    from .motion.cycle import feeding_cycle
    from .motion.laws import CycleSpec
    from .outputs import OutputFolder, write_kinematics_outputs
    from .study.summary import kinematics_summary

    folder = OutputFolder(args.out)
    params = _params(args)
    elevation, spec = _elevation(args, params), CycleSpec(rate=args.rate)
    feeder = load_feeder(params)
    with folder:
        cycle = feeding_cycle(feeder, elevation, spec)
        paths = write_kinematics_outputs(feeder, cycle, folder, _command(args))
    print(kinematics_summary(feeder, cycle))
    print(f"wrote {paths[0]} and figures in {folder.path}")
    return 0


def cmd_cycle(args: argparse.Namespace) -> int:
    """The main study: dynamics of one cycle, cross-checked, with cycle.csv and the figures."""
    from .device.feeder import load_feeder
    from .motion.laws import CycleSpec
    from .outputs import OutputFolder, write_cycle_outputs
    from .study.cycle_study import run_cycle_study
    from .viz.report import FigureWorkers

    folder = OutputFolder(args.out)
    params = _params(args)
    elevation, spec = _elevation(args, params), CycleSpec(rate=args.rate)
    # The figure workers start first: they import matplotlib while this process computes.
    with FigureWorkers(None if args.figures else 1) as workers:
        feeder = load_feeder(params)
        with folder:
            study = run_cycle_study(feeder, elevation, spec, progress=True, forward=args.forward)
            paths = write_cycle_outputs(
                study, folder, _command(args), figures=args.figures, workers=workers
            )
    print(f"{feeder.params.name} feeder")
    print(study.summary())
    figures = f" and {len(paths) - 1} figures" if args.figures else ""
    print(f"wrote {paths[0]}{figures} in {folder.path}")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    """Peak loads over elevations × parameter variants × devices; resumable."""
    from functools import partial

    from .study.grid import elevation_range
    from .study.sweep import run_sweep
    from .viz.report import png_bytes, sweep_figures, write_png

    def figures(table: Path) -> dict[str, partial]:
        return {
            name: partial(write_png, png=png_bytes(fig))
            for name, fig in sweep_figures(table).items()
        }

    elevations = None if args.elevations is None else elevation_range(*args.elevations)
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
        command=_command(args),
    )
    cases = outputs.kept + outputs.computed
    print(
        f"{cases} case{'' if cases == 1 else 's'}: {outputs.kept} kept from the earlier table, "
        f"{outputs.computed} computed"
    )
    count = sum(path.suffix == ".png" for path in outputs.files)
    drawn = f" and {count} figure{'' if count == 1 else 's'}" if count else ""
    print(f"wrote {outputs.table.name}{drawn} in {outputs.table.parent}")
    return 0


def cmd_analyze(args: argparse.Namespace) -> int:
    """A user's closed-chain mechanism: its mobility report (``--check``), or its motion's
    loads and every reaction (``--motion``, ``--out``)."""
    from .study.analyze import analyze, check_mechanism

    if args.check:
        print(check_mechanism(args.closures, args.model, args.pose))
        return 0
    if args.motion is None or args.out is None:
        raise InputError("give --motion FILE and --out DIR (or --check for the mobility report)")
    from .outputs import OutputFolder, write_analysis_outputs

    folder = OutputFolder(args.out)
    analysis = analyze(args.closures, args.motion, args.model, args.pose)
    with folder:
        paths = write_analysis_outputs(analysis, folder, _command(args))
    print(analysis.summary())
    print(_wrote(paths, folder.path))
    return 0


def cmd_simulate(args: argparse.Namespace) -> int:
    """A user's closed-chain mechanism run forward from rest: states.csv, summary, figures."""
    from .outputs import OutputFolder, write_simulation_outputs
    from .study.simulate import simulate_mechanism

    folder = OutputFolder(args.out)
    simulation = simulate_mechanism(
        args.closures,
        args.duration,
        model=args.model,
        pose=args.pose,
        forces=args.forces,
        samples=args.samples,
        method=args.method,
        rtol=args.rtol,
        atol=args.atol,
    )
    with folder:
        paths = write_simulation_outputs(simulation, folder, _command(args))
    print(simulation.summary())
    print(_wrote(paths, folder.path))
    return 0


def _wrote(paths: Sequence[Path], folder: Path) -> str:
    """One line naming a mechanism run's files (the figures counted) and its folder."""
    figures = sum(path.suffix == ".png" for path in paths)
    files = ", ".join(path.name for path in paths if path.suffix != ".png")
    return f"wrote {files} and {figures} figure{'' if figures == 1 else 's'} in {folder}"


def cmd_view(args: argparse.Namespace) -> int:
    """Animate the cycle or a mechanism in MeshCat (127.0.0.1 only) or write it as a static
    HTML page."""
    from .viz.viewer import check_port, check_writable

    html = None if args.html is None else check_writable(args.html)
    port = check_port(args.port)
    if args.model is None:
        return _view_device(args, html, port)
    device = [flag for flag, value in (("--elevation", args.elevation), ("--device",
              args.device), ("--params", args.params)) if value is not None]  # fmt: skip
    if device:
        raise InputError(f"{', '.join(device)}: options of the device's view, not of a MODEL's")
    if args.closures is None:
        raise InputError("give --closures FILE with MODEL (the mechanism file)")
    from .study.view import motion_view, pose_view, run_view
    from .viz.viewer import show_mechanism, write_mechanism_html

    if args.motion is not None:
        view = motion_view(args.closures, args.motion, args.model, args.pose)
    elif args.run_dir is not None:
        view = run_view(args.closures, args.run_dir, args.model, args.pose)
    else:
        view = pose_view(args.closures, args.model, args.pose)
    if html is not None:
        print(f"wrote {write_mechanism_html(view, html, args.reactions, port=port)}")
        return 0
    with show_mechanism(view, args.reactions, port=port) as viewer, suppress(KeyboardInterrupt):
        print(f"{args.model.name} ({view.source}): open {viewer.url}")
        print("press Ctrl-C to stop the viewer", flush=True)
        viewer.serve_forever()
    return 0


def _view_device(args: argparse.Namespace, html: Path | None, port: int | None) -> int:
    """``feeder view --elevation DEG``: the device's cycle."""
    from .device.feeder import load_feeder
    from .dynamics.cycle import cycle_dynamics
    from .viz.viewer import cycle_forces, show_cycle, write_html

    mechanism = [flag for flag, value in (("--closures", args.closures), ("--pose", args.pose),
                 ("--motion", args.motion), ("--run", args.run_dir), ("--reactions",
                 args.reactions)) if value is not None]  # fmt: skip
    if mechanism:
        raise InputError(f"{', '.join(mechanism)}: options of a MODEL's view; give MODEL")
    if args.elevation is None:
        raise InputError("give --elevation DEG for the device's view (or MODEL --closures F)")
    params = _params(args)
    elevation = _elevation(args, params)
    feeder = load_feeder(params)
    dynamics = cycle_dynamics(feeder, elevation, forward=False)
    cycle, forces = dynamics.kinematics, cycle_forces(feeder, dynamics)
    if html is not None:
        print(f"wrote {write_html(feeder, cycle, html, forces, port=port)}")
        return 0
    # Ctrl-C is how the viewer stops: from the first line printed on, it ends with status 0.
    with show_cycle(feeder, cycle, forces, port=port) as viewer, suppress(KeyboardInterrupt):
        print(f"{feeder.params.name} feeder at {args.elevation:g}°: open {viewer.url}")
        print("press Ctrl-C to stop the viewer", flush=True)
        viewer.serve_forever()
    return 0


def _switch(sub: argparse.ArgumentParser, flag: str, dest: str, help: str) -> None:
    """A flag given at most once: ``--no-X`` turns ``dest`` off (default on), any other turns
    it on (default off)."""
    on = not flag.startswith("--no-")
    sub.add_argument(flag, dest=dest, action=_Once, nargs=0, const=on, default=not on, help=help)


def _device_options(sub: argparse.ArgumentParser, default: str) -> None:
    """``--device NAME`` or ``--params FILE`` (one of them)."""
    group = sub.add_mutually_exclusive_group()
    group.add_argument(
        "--device",
        action=_Once,
        choices=sorted(DEVICES),
        help=f"built-in device (default: {default})",
    )
    group.add_argument(
        "--params",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="parameter file (TOML) instead of a built-in device (default: none): write one "
        "with `feeder parameters --format toml --out FILE` and edit its numbers",
    )


def _study_options(sub: argparse.ArgumentParser, out: bool = True, required: bool = True) -> None:
    """``--elevation`` (required if ``required``), ``--out`` (required if ``out``) and the
    device options."""
    sub.add_argument(
        "--elevation",
        action=_Once,
        type=float,
        required=required,
        metavar="DEG",
        help="barrel elevation ε [deg], "
        + ("required" if required else "required for the device (default: none)")
        + ", inside the device's range (−4 … 70 for the built-in ones)",
    )
    if out:
        sub.add_argument(
            "--out",
            action=_Once,
            type=_path,
            required=True,
            metavar="DIR",
            help="output folder, required: new, empty, or one an earlier feeder run wrote (its "
            "outputs are replaced; the manifest feeder-run.json records the run)",
        )
    _device_options(sub, "projectile")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="feeder",
        description="Analysis of the 152 mm SPH M77 ammunition feeding device. SI units, "
        "elevations in degrees. Every command takes --help.",
        allow_abbrev=False,
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name: str, run, help: str) -> argparse.ArgumentParser:
        sub = commands.add_parser(name, help=help, description=help, allow_abbrev=False)
        sub.set_defaults(run=run)
        return sub

    rate_help = "sample rate [Hz] (default: %(default)g)"
    cycle = command("cycle", cmd_cycle, "loads and reactions over a feeding cycle")
    _study_options(cycle)
    cycle.add_argument(
        "--rate",
        action=_Once,
        type=float,
        default=1000.0,
        metavar="HZ",
        help=f"{rate_help}; the force-rule forward run needs ≥ {FORWARD_MIN_RATE:g} Hz with the "
        "default stages (below that, add --no-forward); the loads have no minimum",
    )
    _switch(
        cycle,
        "--no-forward",
        "forward",
        "skip the force-rule forward run and its forward_* columns (default: run it)",
    )
    _switch(
        cycle,
        "--no-figures",
        "figures",
        "write the table and the manifest only, for batch use (default: every figure)",
    )

    kinematics = command("kinematics", cmd_kinematics, "kinematics of the feeding cycle")
    _study_options(kinematics)
    kinematics.add_argument(
        "--rate", action=_Once, type=float, default=1000.0, metavar="HZ", help=rate_help
    )

    view = command(
        "view",
        cmd_view,
        "animate the cycle, or any mechanism (MODEL --closures F), in the browser (MeshCat, "
        "127.0.0.1)",
    )
    _study_options(view, out=False, required=False)
    _mechanism_options(view, required=False)
    source = view.add_mutually_exclusive_group()
    source.add_argument(
        "--motion",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="a mechanism's motion table, analysed as feeder analyze does (default: the "
        "assembled pose with its static loads)",
    )
    source.add_argument(
        "--run",
        dest="run_dir",
        action=_Once,
        type=_path,
        metavar="DIR",
        help="the output folder of an earlier feeder analyze or feeder simulate of the "
        "mechanism (default: none)",
    )
    view.add_argument(
        "--reactions",
        action=_Once,
        nargs="+",
        metavar="JOINT",
        help="joints whose reaction force is drawn (default: the few of largest peak force)",
    )
    view.add_argument(
        "--html",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="write a self-contained HTML page (opens offline) instead of serving "
        "(default: serve until Ctrl-C)",
    )
    view.add_argument(
        "--port",
        action=_Once,
        type=int,
        help="web port on 127.0.0.1 (default: a free one)",
    )

    parameters = command(
        "parameters", cmd_parameters, "every number of a device with its unit and source"
    )
    parameters.add_argument(
        "--format",
        action=_Once,
        choices=("markdown", "toml"),
        default="markdown",
        help="a Markdown table, or a parameter file for --params (default: %(default)s)",
    )
    _device_options(parameters, "every built-in device; projectile with --format toml")
    parameters.add_argument(
        "--out",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="file to write: a new file, or a Markdown table that feeder parameters wrote "
        "(replaced); any other existing file, an edited parameter file (TOML) included, is "
        "refused (default: print)",
    )

    urdf = command("urdf", cmd_urdf, "regenerate the URDF files from the parameters")
    urdf.add_argument(
        "--out",
        action=_Once,
        type=_path,
        default=Path("urdf"),
        metavar="DIR",
        help="folder to write <device>_feeder.urdf into (default: %(default)s)",
    )
    _device_options(urdf, "every built-in device")

    errata = command("errata", cmd_errata, "the paper's errata on the reference cycle")
    errata.add_argument(
        "--out", action=_Once, type=_path, metavar="FILE", help="file to write (default: print)"
    )
    _device_options(errata, "projectile")

    sweep = command("sweep", cmd_sweep, "peak loads over elevations × variants × devices")
    sweep.add_argument(
        "--out",
        action=_Once,
        type=_path,
        required=True,
        metavar="DIR",
        help="output folder, required: new, empty, or one an earlier feeder run wrote (the "
        "manifest feeder-run.json records the run); a sweep already there is resumed, the "
        "outputs of another run are replaced",
    )
    sweep.add_argument(
        "--grid",
        action=_Once,
        type=_path,
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
    sweep.add_argument(
        "--elevations",
        action=_Once,
        nargs=3,
        type=float,
        metavar=("START", "STOP", "STEP"),
        help="elevations [deg], STOP included, replacing the grid's (default: -4 70 1)",
    )
    sweep.add_argument(
        "--workers",
        action=_Once,
        type=int,
        help="local processes (default: every core; 1: this process)",
    )
    sweep.add_argument(
        "--scheduler",
        action=_Once,
        metavar="tcp://HOST:PORT",
        help="run the cases on this Dask cluster (pip install 'feeder[cluster]'; default: "
        "this machine)",
    )
    _switch(
        sweep,
        "--parquet",
        "parquet",
        "also write sweep_peaks.parquet (pip install 'feeder[parquet]'; default: CSV only)",
    )
    _switch(
        sweep,
        "--no-figures",
        "figures",
        "the table only (default: one figure of peaks against elevation per device)",
    )

    analyze = command(
        "analyze", cmd_analyze, "any closed-chain mechanism: mobility, loads, every reaction"
    )
    _mechanism_options(analyze)
    analyze.add_argument(
        "--motion",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="motion table (CSV: t and q_<joint> of the independent joints), required "
        "unless --check (default: none)",
    )
    analyze.add_argument(
        "--out",
        action=_Once,
        type=_path,
        metavar="DIR",
        help="output folder for loads.csv, summary.txt and the figures, required unless "
        "--check (default: none)",
    )
    _switch(
        analyze,
        "--check",
        "check",
        "print the mobility report and the assembled pose instead (default: off)",
    )

    from .chain.dynamics.forward import ATOL, METHODS, RTOL
    from .study.simulate import SAMPLES

    simulate = command(
        "simulate",
        cmd_simulate,
        "any closed-chain mechanism run forward from rest: states, loads, reactions, energy",
    )
    _mechanism_options(simulate)
    simulate.add_argument(
        "--duration",
        action=_Once,
        type=float,
        required=True,
        metavar="SECONDS",
        help="length of the run [s], required",
    )
    simulate.add_argument(
        "--out",
        action=_Once,
        type=_path,
        required=True,
        metavar="DIR",
        help="output folder for states.csv, summary.txt and the figures, required",
    )
    simulate.add_argument(
        "--forces",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="TOML file of more [[force]] elements (default: the mechanism file's only)",
    )
    simulate.add_argument(
        "--samples",
        action=_Once,
        type=int,
        default=SAMPLES,
        metavar="N",
        help=f"output samples over the run, both ends included (default: {SAMPLES})",
    )
    simulate.add_argument(
        "--method",
        action=_Once,
        choices=METHODS,
        default="DOP853",
        help="SciPy integrator: explicit DOP853 or RK45, implicit Radau or BDF for stiff "
        "mechanisms (default: DOP853)",
    )
    simulate.add_argument(
        "--rtol",
        action=_Once,
        type=float,
        default=RTOL,
        help=f"relative tolerance of each step (default: {RTOL:g})",
    )
    simulate.add_argument(
        "--atol",
        action=_Once,
        type=float,
        default=ATOL,
        help=f"absolute tolerance of each step, rad, m and J (default: {ATOL:g})",
    )
    return parser


def _mechanism_options(parser: argparse.ArgumentParser, required: bool = True) -> None:
    """MODEL, ``--closures`` and ``--pose``: a user mechanism, as ``analyze`` and ``simulate``
    take it (``view`` takes it optionally: without MODEL it shows the device)."""
    needed = "required" if required else "required with MODEL (default: none)"
    parser.add_argument(
        "model",
        type=_path,
        nargs=None if required else "?",
        metavar="MODEL",
        help=f"the mechanism's model: URDF (.urdf), MJCF (.xml) or SDF (.sdf), {needed}"
        if required
        else "a mechanism's model: URDF (.urdf), MJCF (.xml) or SDF (.sdf) (default: the device)",
    )
    parser.add_argument(
        "--closures",
        action=_Once,
        type=_path,
        required=required,
        metavar="FILE",
        help=f"mechanism file, {needed}: TOML (cut frames and types, actuated and independent "
        "joints, gravity, force elements, an optional reference pose) or a CAD export's "
        "Extended-URDF YAML (robot.yaml); see docs/MECHANISMS.md",
    )
    parser.add_argument(
        "--pose",
        action=_Once,
        type=_path,
        metavar="FILE",
        help="reference pose (CSV 'joint,value', rad or m) that picks the assembly branch: the "
        "closed pose nearest to it (default: the mechanism file's pose, or the model's zero "
        "pose)",
    )


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line for the terminal: ``feeder: warning: …`` (the package's own), or
    Python's usual form for a library's."""
    if issubclass(category, FeederWarning):
        print(f"feeder: warning: {message}", file=sys.stderr)
    else:
        print(warnings.formatwarning(message, category, filename, lineno, line), file=sys.stderr)


def _check_command(parser: argparse.ArgumentParser, argv: Sequence[str]) -> None:
    """Refuse an unknown command in one line, with the nearest known one (argparse lists all
    of them, without a suggestion)."""
    if not argv or argv[0].startswith("-"):
        return
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if argv[0] in commands.choices:
        return
    near = difflib.get_close_matches(argv[0], list(commands.choices), n=1, cutoff=0.6)
    hint = f"did you mean `feeder {near[0]}`? " if near else ""
    raise InputError(
        f"no command {argv[0]!r}; {hint}commands: {', '.join(commands.choices)} (feeder --help)"
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (2 for bad input, 130 after Ctrl-C)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _terminate) if main_thread else None
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            parser = _parser()
            _check_command(parser, argv)
            args = parser.parse_args(argv)
            args.argv = argv
            return args.run(args)
    except FeederError as exc:
        print(f"feeder: error: {exc}", file=sys.stderr)
        return 2
    except _Terminated:
        print("feeder: terminated (SIGTERM); no output was left half-written", file=sys.stderr)
        return TERMINATED
    except KeyboardInterrupt:
        print("feeder: interrupted (Ctrl-C); no output was left half-written", file=sys.stderr)
        return INTERRUPTED
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
