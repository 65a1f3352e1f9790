"""What a mechanism's side-file says, whatever its format (TOML, Extended-URDF YAML), and the
limits every side-file is read within (:func:`read_side_text`, :func:`check_depth`)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ...validation import did_you_mean
from ..model.base import BaseMotion
from ..model.closure import Closure
from ..model.control import ControlSpec
from ..model.forces import ForceElement
from ..model.points import Point

SIDE_FILE_MAX_BYTES = 100_000
"""Largest side-file read [bytes]. The shipped ones take 0.1–4 kB (the largest,
``examples/andrews_squeezer/reference.toml``, 3.7 kB) and a loop 50–100 bytes, so a mechanism
of a thousand loops fits; PyYAML's pure-Python loader reads ~30 µs a value (measured), so the
largest file (50 000 one-letter values) is read in ~1.5 s."""

SIDE_FILE_MAX_DEPTH = 32
"""Deepest nesting of a side-file's values, the document itself being level 1 and a name or
number the last level. The side-files nest 4 (``closed_loop: [[A, B]]``) to 5 levels
(``[[base.profile]]``); PyYAML and ``tomllib`` parse by recursion and run out of Python's stack
near 300 (TOML) and 1000 (YAML) levels with a ``RecursionError``."""


@dataclass(frozen=True)
class MechanismSpec:
    """What the side-file says.

    Attributes:
        model: Path of the model file (resolved against the side-file's folder).
        model_format: ``"urdf"``, ``"mjcf"`` or ``"sdf"``.
        closures: The cut joints.
        actuated: Actuated joint names.
        independent: Independent joint names.
        gravity: Gravity [m/s²], world frame, (3,), or None (the model's).
        stiffness: Closure label → per-row stiffness (indeterminate-force split).
        joint_types: Joint name → the type that replaces its URDF type
            (:mod:`~feeder.chain.readers.joint_types`).
        forces: The force elements (:mod:`~feeder.chain.model.forces`).
        pose: The reference pose the file gives: (joint, value [rad, m], where it was read)
            (:func:`~feeder.chain.readers.pose.pose_from_values`); empty: the model's zero.
        base: The base's motion (``[base]``), or None: the base stands still, level.
        rates: The initial joint rates of a forward run the file gives: (joint, rate [rad/s,
            m/s], where it was read) (:mod:`~feeder.chain.assembly.rates`; TOML only: an
            Extended-URDF YAML gives none); empty: at rest.
        points: The points whose motion the tables report (``[[point]]``,
            :mod:`~feeder.chain.readers.points`; TOML only).
        control: The joints under control (``[[control]]``,
            :mod:`~feeder.chain.readers.control`; TOML only).
    """

    model: Path
    model_format: str
    closures: tuple[Closure, ...]
    actuated: tuple[str, ...]
    independent: tuple[str, ...]
    gravity: np.ndarray | None = None
    stiffness: dict[str, tuple[float, ...]] = field(default_factory=dict)
    joint_types: dict[str, str] = field(default_factory=dict)
    forces: tuple[ForceElement, ...] = ()
    pose: tuple[tuple[str, float, str], ...] = ()
    base: BaseMotion | None = None
    rates: tuple[tuple[str, float, str], ...] = ()
    points: tuple[Point, ...] = ()
    control: tuple[ControlSpec, ...] = ()


def format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    formats = {".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf", ".sdf": "sdf"}
    if suffix not in formats:
        raise InputError(f"model file {path}: unknown format {suffix!r} (.urdf, .xml/.mjcf, .sdf)")
    return formats[suffix]


def read_side_text(path: Path, kind: str) -> str:
    """The text of the side-file at ``path`` (a ``kind`` file: "TOML" or "YAML"), read only up
    to :data:`SIDE_FILE_MAX_BYTES`.

    Raises:
        InputError: The file cannot be read, is not UTF-8 text, or is larger than the limit.
    """
    try:
        with path.open("rb") as stream:
            data = stream.read(SIDE_FILE_MAX_BYTES + 1)
        if len(data) > SIDE_FILE_MAX_BYTES:
            raise InputError(
                f"{path}: larger than {SIDE_FILE_MAX_BYTES} bytes, the limit of a side-file "
                "(a mechanism's side-file takes a few kB): is it the right file?"
            )
        return data.decode("utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a readable {kind} file: {exc}") from exc


def check_depth(value: object, path: Path, level: int = 1) -> None:
    """Refuse a parsed side-file ``value`` (at nesting ``level``) whose lists and tables nest
    deeper than :data:`SIDE_FILE_MAX_DEPTH`.

    Raises:
        InputError: Too deep (the file and the limit named).
    """
    if level > SIDE_FILE_MAX_DEPTH:
        raise InputError(too_deep(path))
    if isinstance(value, dict):
        value = list(value.values())
    if isinstance(value, list):
        for child in value:
            check_depth(child, path, level + 1)


def table_entries(
    entries: object, section: str, keys: set[str], where: str
) -> Iterator[tuple[str, dict]]:
    """The tables of an array of tables ``[[section]]`` of a side-file, each with where it was
    read (``where [[section]] #k``, for the messages), checked to be tables with only ``keys``.

    Raises:
        InputError: Not a list of tables, an unknown key (named, with the nearest known one).
    """
    if not isinstance(entries, list):
        raise InputError(f"{where}: {section} must be [[{section}]] tables, got {entries!r}")
    for i, entry in enumerate(entries):
        here = f"{where} [[{section}]] #{i + 1}"
        if not isinstance(entry, dict):
            raise InputError(f"{here}: must be a table")
        unknown = sorted(set(entry) - keys)
        if unknown:
            hint = did_you_mean(unknown[0], keys).strip()
            raise InputError(f"{here}: unknown keys {unknown}" + (f"; {hint}" if hint else ""))
        yield here, entry


def tables_file(path: Path, section: str) -> list:
    """The ``[[section]]`` tables (as parsed) of a TOML file that holds only those (``--forces
    FILE``, ``--control FILE``): read as a side-file is (:func:`read_side_text`, the size
    limit), another section refused with the nearest name.

    Raises:
        InputError: An unreadable or malformed file, another section.
    """
    import tomllib  # here: the YAML side-files' readers do not need it

    try:
        document = tomllib.loads(read_side_text(path, "TOML"))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not a readable TOML file: {exc}") from exc
    other = sorted(set(document) - {section})
    if other:
        hint = did_you_mean(other[0], [section]).strip()
        raise InputError(
            f"{path}: only [[{section}]] tables are expected, got {other}"
            + (f"; {hint}" if hint else "")
        )
    return document.get(section, [])


def too_deep(path: Path, where: str = "") -> str:
    """The message that refuses a side-file nested deeper than :data:`SIDE_FILE_MAX_DEPTH`
    (``where``: e.g. " at line 3")."""
    return (
        f"{path}: values nested deeper than {SIDE_FILE_MAX_DEPTH} levels{where}, the limit of a "
        "side-file (its lists of names nest 4 levels)"
    )
