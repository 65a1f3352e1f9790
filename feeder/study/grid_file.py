"""The grid file of a sweep (TOML): read and checked into a :class:`~feeder.study.grid.SweepGrid`.

Every key is optional::

    devices = ["projectile", "charge"]     # built-in devices (default: ["projectile"])
    elevations = {start = -4, stop = 70, step = 1}   # [deg], stop included on a step (the default)
    # elevations = [-4, 0, 30, 70]         # or a list [deg]
    rate = 1000.0                          # sample rate [Hz] (default 1000)
    durations = [1.0, 1.0, 2.0]            # stage durations [s] (default 1, 1, 2)

    [[variants]]                           # default: one variant, "reference", no change
    name = "reference"

    [[variants]]
    name = "heavier"
    mass_factor = 1.2                      # the payload 20 % heavier and 15 % longer, moments
    length_factor = 1.15                   # and centre of gravity with it (feeder.retrofit)

    [[variants]]
    name = "pivot_up"
    L2 = 0.29                              # any number of the parameter set, by its name in
                                           # PARAMETERS.md, in its SI unit there

    [[variants]]                           # a vehicle case: the device on a moving or tilted
    name = "side_slope_terrain"            # base, as a mechanism file's [base] (no forward:
    base = {roll_deg = 15.0}               # the device's is fixed): a slope, a hull table,
    [[variants.base.profile]]              # profiles (feeder.chain.readers.base_motion)
    type = "terrain"

    [[variants]]                           # the loading run under control on that base: the
    name = "terrain_controlled"            # loading pose against the rammer's line (the
    forward = "controlled"                 # table's loading_* and controlled_* columns)
    servo = {bandwidth_hz = 8.0}           # optional: feeder.dynamics.servo.ServoGains' fields
    [[variants.base.profile]]
    type = "terrain"

Each variant applies to every device (:mod:`feeder.study.grid` makes the grid and its cases, and
checks it before any cycle is computed).
"""

from __future__ import annotations

import dataclasses
import tomllib
from pathlib import Path

import numpy as np

from ..chain.readers import read_base
from ..device.parameters import VEHICLE_FORWARD
from ..dynamics.servo import ServoGains
from ..exceptions import FeederError, InputError
from ..motion.laws import CycleSpec
from ..validation import check_elevations_deg
from .grid import SweepGrid, Variant, elevation_range, make_grid


def _variant(entry: object, index: int, folder: Path) -> Variant:
    if not isinstance(entry, dict) or "name" not in entry:
        raise InputError(f"variants[{index}] must be a table with a name, got {entry!r}")
    base = None
    if "base" in entry:
        base = read_base(entry["base"], folder, f"variants[{index}]", VEHICLE_FORWARD)
    forward = entry.get("forward")
    if forward not in (None, "controlled"):
        raise InputError(
            f"variants[{index}]: forward = {forward!r}; a sweep's forward run is "
            '"controlled" (the force-rule run is a check of one cycle: feeder cycle)'
        )
    settings = entry.get("servo", {})
    if not isinstance(settings, dict):
        raise InputError(f"variants[{index}]: servo must be a table, got {settings!r}")
    if settings and forward is None:
        raise InputError(
            f'variants[{index}]: servo sets the controlled run: add forward = "controlled"'
        )
    names = {field.name for field in dataclasses.fields(ServoGains)}
    unknown = sorted(set(settings) - names)
    if unknown:
        keys = ", ".join(sorted(names))
        raise InputError(f"variants[{index}]: unknown servo keys {unknown}; a servo has {keys}")
    servo = None if forward is None else ServoGains(**settings)
    changes = tuple((k, v) for k, v in entry.items() if k not in VARIANT_KEYS)
    return Variant(entry["name"], changes, base, servo)


VARIANT_KEYS = ("name", "base", "forward", "servo")
"""A variant's keys besides the parameter changes."""


def _elevations(value: object) -> np.ndarray:
    if isinstance(value, dict):
        unknown = set(value) - {"start", "stop", "step"}
        if unknown or not {"start", "stop"} <= set(value):
            raise InputError(
                f"elevations: a table needs start and stop [deg] and may have step, got {value!r}"
            )
        return elevation_range(value["start"], value["stop"], value.get("step", 1.0))
    if isinstance(value, list):
        return np.array(check_elevations_deg(value, None))
    raise InputError(f"elevations must be a list or {{start, stop, step}} [deg], got {value!r}")


GRID_KEYS = ("devices", "elevations", "rate", "durations", "variants")
"""The keys a grid file may have."""


def read_grid(path: str | Path) -> SweepGrid:
    """Read and check a grid file (TOML, the format of this module's docstring).

    Raises:
        InputError: A missing or unreadable file, invalid TOML, an unknown key.
        FeederError: Any error of :func:`make_grid`, its message prefixed with the file.
    """
    path = Path(path)
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except OSError as exc:
        raise InputError(f"cannot read the grid file {path}: {exc.strerror or exc}") from exc
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"{path} is not a TOML grid file: {exc}") from exc
    try:
        unknown = sorted(set(document) - set(GRID_KEYS))
        if unknown:
            raise InputError(f"unknown keys {unknown}; a grid has {', '.join(GRID_KEYS)}")
        spec = CycleSpec(
            durations=document.get("durations", CycleSpec.durations),
            rate=document.get("rate", CycleSpec.rate),
        )
        variants = document.get("variants", [{"name": "reference"}])
        if not isinstance(variants, list):
            raise InputError(f"variants must be an array of tables, got {variants!r}")
        return make_grid(
            devices=document.get("devices", ["projectile"]),
            elevations_deg=(
                _elevations(document["elevations"]) if "elevations" in document else None
            ),
            variants=[_variant(entry, k, path.parent) for k, entry in enumerate(variants)],
            spec=spec,
        )
    except FeederError as exc:
        raise type(exc)(f"{path}: {exc}") from exc


def as_grid(grid: str | Path | SweepGrid) -> SweepGrid:
    """``grid`` as a checked grid: a grid file's path read (:func:`read_grid`), a
    :class:`~feeder.study.grid.SweepGrid` as it is.

    Raises:
        InputError: Neither a path nor a grid; any error of :func:`read_grid`.
    """
    if isinstance(grid, SweepGrid):
        return grid
    if isinstance(grid, str | Path):
        return read_grid(grid)
    raise InputError(f"grid must be a TOML file's path or a SweepGrid, got {grid!r}")
