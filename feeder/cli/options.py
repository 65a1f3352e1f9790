"""The command line's shared parts: options given once, the option groups every command spells
alike (``--device``, ``--params``, ``--elevation``, ``--out``, ``--elevations``, ``--workers``,
``--scheduler``; a user mechanism's MODEL, ``--closures``, ``--pose``), and the small
conversions between arguments and the package."""

from __future__ import annotations

import argparse
import math
import shlex
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..device.builtin import DEVICES
from ..exceptions import InputError
from ..validation import check_elevation, check_number, check_path

if TYPE_CHECKING:
    from ..chain.model.base import BaseMotion
    from ..device.parameters import FeederParameters


RATE_HELP = "sample rate [Hz] (default: %(default)g)"
"""Help of ``--rate`` (cycle, kinematics, design sensitivities)."""


def add_command(
    commands: argparse._SubParsersAction,
    name: str,
    run: Callable[[argparse.Namespace], int],
    help: str,
) -> argparse.ArgumentParser:
    """A sub-parser ``name`` that calls ``run(args)``; the help is also its description."""
    sub = commands.add_parser(name, help=help, description=help, allow_abbrev=False)
    sub.set_defaults(run=run)
    return sub


FORWARD_MIN_RATE = 500.0
"""Lowest sample rate [Hz] at which the force-rule forward run tracks the default stages within
its 1e-4 rad check (3.8e-5 rad at 500 Hz, 1.2e-4 rad at 400 Hz: the table in
:mod:`feeder.dynamics.cycle`). Stated in ``feeder cycle --help``."""


class Once(argparse.Action):
    """Store an option's value, or its constant for a flag (``nargs=0``); a second occurrence
    is an error (argparse would silently keep the last: ``--elevation 10 --elevation 20``)."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", set())
        if self.dest in given:
            parser.error(f"{'/'.join(self.option_strings)} given twice: give it once")
        given.add(self.dest)
        setattr(namespace, self.dest, self.const if self.nargs == 0 else values)


def path_argument(text: str) -> Path:
    """An argument naming a file or folder (:func:`~feeder.validation.check_path`)."""
    try:
        return check_path("the path", text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from exc


def rate_argument(text: str) -> tuple[str, float]:
    """``JOINT=VALUE``: a joint's name and its rate [rad/s, m/s], a finite number
    (``feeder simulate --rate``)."""
    name, sign, value = text.partition("=")
    if not sign or not name.strip():
        raise argparse.ArgumentTypeError(f"expected JOINT=VALUE (rad/s or m/s), got {text!r}")
    try:
        return name.strip(), check_number(f"the rate of {name.strip()!r}", float(value))
    except (ValueError, InputError):
        raise argparse.ArgumentTypeError(
            f"the rate of {name.strip()!r} must be a finite number [rad/s or m/s], got "
            f"{value.strip()!r}"
        ) from None


def params_of(args: argparse.Namespace) -> FeederParameters:
    """The parameter set of ``--params FILE`` (read and checked) or of ``--device NAME``."""
    if args.params is not None:
        from ..device.parameter_file import read_parameters

        return read_parameters(args.params)
    return DEVICES[args.device or "projectile"]


def elevation_of(args: argparse.Namespace, params: FeederParameters) -> float:
    """The ``--elevation`` option [deg] in radians, checked against the device's range."""
    degrees = check_number("elevation [deg]", args.elevation)
    return check_elevation(math.radians(degrees), params.elevation_limits)


def command_line(args: argparse.Namespace) -> str:
    """The command line as typed, for the output folder's manifest."""
    return shlex.join(["feeder", *args.argv])


def write_or_print(text: str, out: Path | None) -> None:
    from ..files import write_text

    if out is None:
        print(text, end="")
    else:
        print(f"wrote {write_text(out, text)}")


def wrote(paths: Sequence[Path], folder: Path) -> str:
    """One line naming a mechanism run's files (the figures counted) and its folder."""
    figures = sum(path.suffix == ".png" for path in paths)
    files = ", ".join(path.name for path in paths if path.suffix != ".png")
    return f"wrote {files} and {figures} figure{'' if figures == 1 else 's'} in {folder}"


def switch(sub: argparse.ArgumentParser, flag: str, dest: str, help: str) -> None:
    """A flag given at most once: ``--no-X`` turns ``dest`` off (default on), any other turns
    it on (default off)."""
    on = not flag.startswith("--no-")
    sub.add_argument(flag, dest=dest, action=Once, nargs=0, const=on, default=not on, help=help)


def figures_switch(sub: argparse.ArgumentParser) -> None:
    """``--no-figures`` of a mechanism's study (``analyze``, ``simulate``): its table, summary,
    assembled pose and manifest only, no PNG and no report.html."""
    switch(
        sub,
        "--no-figures",
        "figures",
        "write the table, summary.txt, assembled_pose.csv and the manifest only, no figures and "
        "no report.html, for batch use (default: every figure and report.html)",
    )


def device_options(sub: argparse.ArgumentParser, default: str) -> None:
    """``--device NAME`` or ``--params FILE`` (one of them)."""
    group = sub.add_mutually_exclusive_group()
    group.add_argument(
        "--device",
        action=Once,
        choices=sorted(DEVICES),
        help=f"built-in device (default: {default})",
    )
    group.add_argument(
        "--params",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="parameter file (TOML) instead of a built-in device (default: none): write one "
        "with `feeder parameters --format toml --out FILE` and edit its numbers",
    )


def base_options(sub: argparse.ArgumentParser) -> None:
    """``--slope PITCH ROLL`` and ``--base-motion FILE|PROFILE``: the device on a vehicle."""
    sub.add_argument(
        "--slope",
        action=Once,
        type=float,
        nargs=2,
        metavar=("PITCH", "ROLL"),
        help="the hull standing on a slope [deg] (ISO 8855: a positive pitch lowers the nose, a "
        "positive roll the right side; default: level)",
    )
    sub.add_argument(
        "--base-motion",
        action=Once,
        metavar="FILE|PROFILE",
        help="the hull's motion (default: at rest): a hull table (.csv: t, x, y, z [m], roll, "
        "pitch, yaw [rad] or *_deg, optional v_*/a_* rates), a file with a [base] table (.toml), "
        "or a profile terrain | bump | recoil with parameters, e.g. terrain:heave=0.05,"
        "pitch_deg=2 (docs/REFERENCE.md)",
    )


def base_of(args: argparse.Namespace) -> BaseMotion | None:
    """The device's base from ``--slope`` and ``--base-motion`` (None: standing level).

    Raises:
        InputError: A bad slope, an unreadable file, an unknown profile or parameter.
    """
    from ..chain.model.base import BaseMotion
    from ..chain.model.profiles import PROFILES, Slope
    from ..chain.readers.base_motion import (
        parse_profile,
        profile_name,
        read_base_file,
        read_hull_table,
    )
    from ..device.parameters import VEHICLE_FORWARD

    profiles = []
    if args.slope is not None:
        pitch, roll = (check_number(f"slope {name} [deg]", x) for name, x in zip(
            ("pitch", "roll"), args.slope, strict=True))  # fmt: skip
        profiles.append(Slope(math.radians(pitch), math.radians(roll)))
    motion = args.base_motion
    if motion is not None:
        path = Path(motion)
        suffix = path.suffix.lower()
        if suffix == ".csv":
            profiles.append(read_hull_table(motion))
        elif suffix == ".toml":
            profiles += read_base_file(motion, VEHICLE_FORWARD).profiles
        elif profile_name(motion) not in PROFILES and path.exists():
            # a file or folder of another kind (a folder named as a profile is the profile)
            what = "a folder" if path.is_dir() else "neither a hull table (.csv) nor a .toml file"
            raise InputError(f"--base-motion {motion} is {what}: give a file or a profile")
        else:
            profiles.append(parse_profile(motion))
    return BaseMotion(tuple(profiles), VEHICLE_FORWARD) if profiles else None


def study_options(sub: argparse.ArgumentParser, out: bool = True, required: bool = True) -> None:
    """``--elevation`` (required if ``required``), ``--out`` (required if ``out``) and the
    device options."""
    sub.add_argument(
        "--elevation",
        action=Once,
        type=float,
        required=required,
        metavar="DEG",
        help="barrel elevation ε [deg], "
        + ("required" if required else "required for the device (default: none)")
        + ", inside the device's range (−4 … 70 for the built-in ones)",
    )
    if out:
        out_option(sub)
    device_options(sub, "projectile")


def out_option(sub: argparse.ArgumentParser) -> None:
    """``--out DIR``, required: a study's output folder (:class:`feeder.files.OutputFolder`)."""
    sub.add_argument(
        "--out",
        action=Once,
        type=path_argument,
        required=True,
        metavar="DIR",
        help="output folder, required: new, empty, or one an earlier feeder run wrote (its "
        "outputs are replaced; the manifest feeder-run.json records the run)",
    )


def typed(numbers: Sequence[float]) -> str:
    """Numbers as they are typed on the command line: ``-4 70 2``."""
    return " ".join(f"{x:g}" for x in numbers)


def elevations_option(
    sub: argparse.ArgumentParser, default_text: str, what: str = "elevations"
) -> None:
    """``--elevations START STOP STEP`` [deg] (:func:`~feeder.study.grid.elevation_range`);
    ``what`` they are and ``default_text`` (what applies without them) for the help."""
    sub.add_argument(
        "--elevations",
        action=Once,
        nargs=3,
        type=float,
        metavar=("START", "STOP", "STEP"),
        help=f"{what} [deg], STOP included when on a step (default: {default_text})",
    )


def parallel_options(sub: argparse.ArgumentParser, runs: str = "the cycles") -> None:
    """``--workers N`` and ``--scheduler tcp://HOST:PORT``: where ``runs`` run
    (:func:`~feeder.study.sweep.sweep_executor`)."""
    sub.add_argument(
        "--workers",
        action=Once,
        type=int,
        help="local processes (default: every core; 1: this process)",
    )
    sub.add_argument(
        "--scheduler",
        action=Once,
        metavar="tcp://HOST:PORT",
        help=f"run {runs} on this Dask cluster (pip install 'feeder[cluster]'; default: this "
        "machine)",
    )


def mechanism_options(parser: argparse.ArgumentParser, required: bool = True) -> None:
    """MODEL, ``--closures`` and ``--pose``: a user mechanism, as ``analyze`` and ``simulate``
    take it (``view`` takes it optionally: without MODEL it shows the device)."""
    needed = "required" if required else "required with MODEL (default: none)"
    parser.add_argument(
        "model",
        type=path_argument,
        nargs=None if required else "?",
        metavar="MODEL",
        help=f"the mechanism's model: URDF (.urdf), MJCF (.xml) or SDF (.sdf), {needed}"
        if required
        else "a mechanism's model: URDF (.urdf), MJCF (.xml) or SDF (.sdf) (default: the device)",
    )
    parser.add_argument(
        "--closures",
        action=Once,
        type=path_argument,
        required=required,
        metavar="FILE",
        help=f"mechanism file, {needed}: TOML (cut frames and types, actuated and independent "
        "joints, gravity, force elements, an optional reference pose) or a CAD export's "
        "Extended-URDF YAML (robot.yaml); see docs/MECHANISMS.md",
    )
    parser.add_argument(
        "--pose",
        action=Once,
        type=path_argument,
        metavar="FILE",
        help="reference pose (CSV 'joint,value', rad or m) that picks the assembly branch: the "
        "closed pose nearest to it (default: the mechanism file's pose, or the model's zero "
        "pose)",
    )
