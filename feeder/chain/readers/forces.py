"""Force elements read from a mechanism file's ``[[force]]`` tables (TOML), or from a file of
only those (``feeder simulate --forces F``). Units SI; vectors in world axes; table files are CSV
with a header, relative to the file that names them::

    [[force]]
    type = "spring"                 # point-to-point spring–damper–actuator
    frames = ["D_body3", "C_ground"]
    stiffness = 4530.0              # [N/m]
    rest_length = 0.07785           # [m]
    damping = 0.0                   # [N·s/m]
    force = 0.0                     # [N] the actuator's push (extending), or
    force_table = "push.csv"        # columns t, force

    [[force]]
    type = "cylinder"               # hydraulic cylinder, cap end first
    frames = ["cap", "rod_end"]
    bore = 0.08                     # [m]
    rod = 0.045                     # [m]
    pressure = 12e6                 # [Pa] cap side, or pressure_table = "p.csv" (t, pressure)
    rod_pressure = 0.0              # [Pa] rod side, or rod_pressure_table = "…" (t, pressure)
    damping = 0.0                   # [N·s/m]

    [[force]]
    type = "joint_spring"           # torsion (revolute) or linear (prismatic) spring–damper
    joint = "rocker_joint"
    stiffness = 0.2                 # [N·m/rad] or [N/m]
    rest = 1.0                      # [rad] or [m]
    damping = 0.0                   # [N·m·s/rad] or [N·s/m]
    preload = 0.0                   # [N·m] or [N], the resistance at rest

    [[force]]
    type = "load"                   # a force and a moment on a frame's body, at its origin
    frame = "body1"
    force = [0.0, 0.0, 0.0]         # [N]
    moment = [0.0, 0.0, 0.033]      # [N·m], or table = "load.csv" (t, fx, fy, fz, mx, my, mz)

Each may have a ``name`` (its label in the results).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ...validation import check_file
from ..model.forces import Cylinder, ForceElement, JointSpring, Load, Spring, Table
from .motion_table import read_columns
from .spec import tables_file

KINDS: dict[str, type] = {
    "spring": Spring,
    "cylinder": Cylinder,
    "joint_spring": JointSpring,
    "load": Load,
}
"""The ``type`` of a ``[[force]]`` table and the element it makes."""

REQUIRED = {
    kind: tuple(
        f.name
        for f in dataclasses.fields(cls)
        if f.init and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    )
    for kind, cls in KINDS.items()
}
"""The keys each ``type`` must give: its element's fields without a default, in their order."""

KEYS = {
    "spring": {"frames", "stiffness", "rest_length", "damping", "force", "force_table"},
    "cylinder": {
        "frames", "bore", "rod", "pressure", "pressure_table", "rod_pressure",
        "rod_pressure_table", "damping",
    },
    "joint_spring": {"joint", "stiffness", "rest", "damping", "preload"},
    "load": {"frame", "force", "moment", "table"},
}  # fmt: skip
"""The keys of each ``type`` (besides ``type`` and ``name``)."""


def read_forces(entries: object, folder: Path, where: str) -> tuple[ForceElement, ...]:
    """The force elements of a list of ``[[force]]`` tables; table files relative to ``folder``.

    Raises:
        InputError: Not a list of tables, an unknown type or key, a missing or bad value, a
            missing or malformed table file (each named with the entry's number).
    """
    if not isinstance(entries, list):
        raise InputError(f"{where}: [[force]] must be a list of tables")
    return tuple(
        _element(entry, folder, f"{where} [[force]] #{i + 1}") for i, entry in enumerate(entries)
    )


def read_force_file(path: Path) -> tuple[ForceElement, ...]:
    """The force elements of a TOML file holding only ``[[force]]`` tables.

    Raises:
        InputError: A path that is not text or a path, a missing or unreadable file, another
            section, a bad element.
    """
    path = check_file("force file", path)
    return read_forces(tables_file(path, "force"), path.parent, str(path))


def read_table(path: str | Path, columns: tuple[str, ...]) -> Table:
    """A force table: a CSV file with the header ``t`` and ``columns`` in that order [s and SI
    units], linearly interpolated in time.

    Raises:
        InputError: A missing or unreadable file, another header, a value that is not a finite
            number, fewer than two rows, times that do not increase.
    """
    path, header, values = read_columns(path, "the force table")
    if tuple(header) != ("t", *columns):
        raise InputError(f"{path}: the header must be {['t', *columns]}, got {header}")
    return Table(
        values["t"],
        np.column_stack([values[name] for name in columns]),
        source=f"force table {path.name}",
    )


def _element(entry: object, folder: Path, where: str) -> ForceElement:
    if not isinstance(entry, dict):
        raise InputError(f"{where}: must be a table")
    kind = entry.get("type")
    if kind not in KEYS:
        raise InputError(f"{where}: 'type' must be one of {sorted(KEYS)}, got {kind!r}")
    unknown = set(entry) - KEYS[kind] - {"type", "name"}
    if unknown:
        raise InputError(f"{where}: unknown keys {sorted(unknown)} for a {kind}")
    name = entry.get("name", "")
    if not isinstance(name, str):
        raise InputError(f"{where}: 'name' must be text, got {name!r}")
    values = {key: value for key, value in entry.items() if key not in ("type", "name")}
    for key, columns in (
        ("force_table", ("force",)),
        ("pressure_table", ("pressure",)),
        ("rod_pressure_table", ("pressure",)),
        ("table", ("fx", "fy", "fz", "mx", "my", "mz")),
    ):
        if key in values:
            target = key.removesuffix("_table")
            if target != key and target in values:
                raise InputError(f"{where}: give '{target}' or '{key}', not both")
            if not isinstance(values[key], str):
                raise InputError(f"{where}: '{key}' must name a CSV file, got {values[key]!r}")
            try:
                values[target] = read_table(folder / values.pop(key), columns)
            except InputError as exc:
                raise InputError(f"{where}: {exc}") from exc
    missing = [key for key in REQUIRED[kind] if key not in values]
    if missing:
        raise InputError(f"{where}: a {kind} needs {', '.join(map(repr, missing))}")
    if "frames" in values:
        values["frames"] = tuple(values["frames"])
    try:
        return KINDS[kind](name=name, **values)
    except (InputError, TypeError) as exc:
        raise InputError(f"{where}: {exc}") from exc
