"""The parameter file: one device's parameters as TOML, every number with its unit and source.

``feeder parameters --format toml`` writes it (:func:`parameters_toml`); ``--params FILE`` on
every command reads it (:func:`read_parameters`). A user with the real drawings edits the
numbers there instead of the package source. Units: metres, kilograms and kg·m² as in
:class:`FeederParameters`, and angles in degrees, under their field's name with ``_deg`` added
(``swing_deg = 90.0``; read back into radians). Every number is written with the fewest digits
that give it back to :data:`DIGITS` (``b = 0.05``, not ``0.04999999999999999``). Every field is
required and no other is allowed, so that a mistyped name is an error rather than a default
(a file with angles in radians, as feeder wrote before, names the ``_deg`` field it lacks).

The file is read with the standard library's ``tomllib`` and written here: TOML writers do not
keep comments, and the units are in the comments.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from dataclasses import fields
from pathlib import Path

from ..exceptions import FeederError, InputError
from ..validation import check_file
from .loop import check_device
from .parameters import FeederParameters, LinkInertia

_INERTIA_KEYS = ("mass", "moments", "source")

NAME = re.compile(r"\w[\w.-]*")
"""A parameter file's ``name``: letters, digits, ``_``, ``-`` and ``.``, not starting with ``.``
or ``-``. It names files (``feeder urdf`` writes ``<name>_feeder.urdf``), so it must not be
able to name a folder."""


TOML_MARKER = "written by `feeder parameters --format toml`"
"""On the first line of every parameter file that :func:`parameters_toml` writes."""

DIGITS = 1e-12
"""Relative precision [-] to which the file gives each number back: drawings give 3–5 digits,
and the numbers computed from them (Table I's differences) carry round-off of ~1e-16 that
twelve digits drop (0.04999999999999999 is written 0.05)."""


def decimal(value: float) -> str:
    """``value`` as the shortest decimal within :data:`DIGITS` of it, a TOML float."""
    for digits in range(1, 18):
        text = f"{value:.{digits}g}"
        if abs(float(text) - value) <= DIGITS * abs(value):
            break
    return repr(float(text))  # Python's float repr is a TOML float: 90.0, 0.05, 1e-05


def key_of(name: str, unit: str) -> str:
    """A field's key in the file: an angle's carries ``_deg`` (its value is in degrees)."""
    return f"{name}_deg" if unit == "rad" else name


def parameters_toml(params: FeederParameters) -> str:
    """The parameter file of ``params``: TOML, a comment with the unit and source of each value.

    Reading it back (:func:`read_parameters`) gives ``params`` to :data:`DIGITS`, and reading
    and writing again gives the same file.
    """
    lines = [
        f"# Parameters of the {params.name} feeder: {TOML_MARKER},",
        "# read by `--params FILE` on every feeder command. Edit the numbers, keep every field.",
        "# Units in each comment: m, kg, kg·m², and degrees for the angles (keys ending _deg).",
        "# Link inertia tables: Table I's moments about axes through the centre of gravity,",
        "# parallel to the link frame (feeder/device/parameters.py explains the frames).",
        "",
    ]
    tables = []
    for field in fields(params):
        value = getattr(params, field.name)
        if isinstance(value, LinkInertia):
            tables += [
                "",
                f"[{field.name}]",
                f"mass = {decimal(value.mass)}  # [kg]",
                f"moments = [{', '.join(decimal(float(m)) for m in value.moments)}]  "
                "# [kg·m²] Ixx, Iyy, Izz",
                f"source = {_string(value.source)}",
            ]
            continue
        unit, source = field.metadata["unit"], field.metadata["source"]
        if isinstance(value, str):
            comment = f"  # {source}" if source != "-" else ""
            lines.append(f"{field.name} = {_string(value)}{comment}")
        else:
            shown = decimal(math.degrees(value) if unit == "rad" else float(value))
            label = "deg" if unit == "rad" else unit
            lines.append(f"{key_of(field.name, unit)} = {shown}  # [{label}]; {source}")
    return "\n".join(lines + tables) + "\n"


def parameters_sha256(params: FeederParameters) -> str:
    """SHA-256 of the parameter file of ``params``: one hash per parameter set, however the
    file it came from was formatted."""
    return hashlib.sha256(parameters_toml(params).encode("utf-8")).hexdigest()


def read_parameters(path: str | Path) -> FeederParameters:
    """Read and check a parameter file written by :func:`parameters_toml` (and edited).

    Every check of :func:`~feeder.device.loop.check_device` runs: the numbers, each link's
    inertia, and the loop over the whole arm travel.

    Raises:
        InputError: The file is missing or unreadable, is not TOML, lacks a field or has an
            unknown one, holds a value of the wrong type, a name that is not :data:`NAME`, or a
            parameter set that fails a check; the message names the file and the field.
    """
    path = check_file("parameter file", path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the parameter file {path}: {exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path} is not a TOML parameter file: {exc}") from exc
    values = {}
    keys = {f.name: key_of(f.name, f.metadata.get("unit", "")) for f in fields(FeederParameters)}
    _check_keys(path, "", data, list(keys.values()))
    for field in fields(FeederParameters):
        key = keys[field.name]
        value = data[key]
        if field.type == "LinkInertia":
            values[field.name] = _inertia(path, field.name, value)
        elif field.type == "str":
            values[field.name] = _text(path, field.name, value)
        elif key != field.name:  # an angle, in degrees in the file
            values[field.name] = math.radians(_number(path, key, value, "deg"))
        else:
            values[field.name] = _number(path, field.name, value, field.metadata["unit"])
    if not NAME.fullmatch(values["name"]):
        raise InputError(
            f"{path}: name must be letters, digits, '_', '-' or '.', not starting with '.' or "
            f"'-' (it names files), got {values['name']!r}: rename it"
        )
    params = FeederParameters(**values)
    try:
        check_device(params)
    except FeederError as exc:
        raise InputError(f"{path}: {exc}") from exc
    return params


def _string(text: str) -> str:
    """``text`` as a TOML basic string (JSON's escapes are TOML's)."""
    return json.dumps(text, ensure_ascii=False)


def _check_keys(path: Path, table: str, data: object, expected: list[str]) -> None:
    where = f"table [{table}]" if table else "the file"
    if not isinstance(data, dict):
        raise InputError(f"{path}: {table} must be a table ([{table}]), got {data!r}")
    unknown = [key for key in data if key not in expected]
    if unknown:
        raise InputError(f"{path}: unknown field {unknown[0]!r} in {where}; fields: {expected}")
    missing = [key for key in expected if key not in data]
    if missing:
        raise InputError(f"{path}: missing field {missing[0]!r} in {where}")


def _number(path: Path, name: str, value: object, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(f"{path}: {name} must be a number [{unit}], got {value!r}")
    if not math.isfinite(value):
        raise InputError(f"{path}: {name} must be finite [{unit}], got {value!r}")
    return float(value)


def _text(path: Path, name: str, value: object) -> str:
    if not isinstance(value, str):
        raise InputError(f"{path}: {name} must be a string, got {value!r}")
    return value


def _inertia(path: Path, name: str, value: object) -> LinkInertia:
    _check_keys(path, name, value, list(_INERTIA_KEYS))
    moments = value["moments"]
    if not isinstance(moments, list) or len(moments) != 3:
        raise InputError(
            f"{path}: {name}.moments must be three numbers [kg·m²] (Ixx, Iyy, Izz), "
            f"got {moments!r}"
        )
    return LinkInertia(
        _number(path, f"{name}.mass", value["mass"], "kg"),
        tuple(_number(path, f"{name}.moments", m, "kg·m²") for m in moments),
        _text(path, f"{name}.source", value["source"]),
    )
