"""The base's motion from files and the command line: a mechanism file's ``[base]`` table, a hull
motion table (CSV), and profile names with their parameters (:mod:`feeder.chain.model.base`).

In a TOML mechanism file::

    [base]
    forward = [1.0, 0.0, 0.0]   # the vehicle's forward axis in the model's axes (default x)
    pitch_deg = 0.0             # a slope: the hull's pitch and roll [°] (ISO 8855 signs)
    roll_deg = 15.0
    table = "hull.csv"          # optional: the hull's motion in time (read_hull_table)

    [[base.profile]]            # optional, any number: terrain | bump | recoil
    type = "terrain"
    heave = 0.04                # [m]; angles as <name>_deg [°]; unset: the profile's default
    pitch_deg = 3.0

The hull table (CSV, header row): ``t`` [s] and any of the channels ``x``, ``y``, ``z`` [m],
``roll``, ``pitch``, ``yaw`` [rad] (or ``roll_deg`` … [°]), their rates ``v_<channel>`` and
accelerations ``a_<channel>`` (same unit rule, per second and per second²); a channel left out is
zero, rates left out are differentiated from the values (``numpy.gradient``, second order), rates
given are checked against them as a motion table's are
(:func:`~feeder.chain.readers.motion_table.check_rates`).

On the command line a profile is ``NAME`` or ``NAME:key=value,key=value`` (the keys above).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import tomllib
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ...validation import check_file, check_finite, check_number
from ..model.base import BaseMotion
from ..model.channels import HullProfile
from ..model.forces import Table
from ..model.hull import CHANNELS
from ..model.hull_table import COLUMNS, HullTable
from ..model.profiles import PROFILES, Slope
from .motion_table import check_rates, read_columns

BASE_KEYS = {"forward", "pitch_deg", "roll_deg", "table", "profile"}
"""Keys a ``[base]`` table may have."""


def profile_keys(name: str) -> list[str]:
    """The parameter keys of the profile ``name`` (angles as ``<field>_deg``)."""
    kind = PROFILES[name]
    return [f"{f.name}_deg" if f.name in kind.ANGLES else f.name for f in dataclasses.fields(kind)]


def make_profile(name: object, values: dict, where: str) -> HullProfile:
    """The profile ``name`` (:data:`~feeder.chain.model.profiles.PROFILES`) with the parameters
    ``values`` (keys of :func:`profile_keys`; angles in degrees), the others at their defaults.

    Raises:
        InputError: An unknown profile or key (the known ones listed), a value that is not a
            number or is out of range.
    """
    if name not in PROFILES:
        raise InputError(f"{where}: unknown base profile {name!r}; profiles: {sorted(PROFILES)}")
    kind = PROFILES[name]
    known = profile_keys(name)
    unknown = sorted(set(values) - set(known))
    if unknown:
        raise InputError(f"{where}: profile {name!r} has no parameters {unknown}; it has {known}")
    arguments = {}
    for key, value in values.items():
        number = check_number(f"{where} {key}", value)
        if key.endswith("_deg"):
            arguments[key[:-4]] = math.radians(number)
        else:
            arguments[key] = number
    with _within(where):
        return kind(**arguments)


@contextlib.contextmanager
def _within(where: str) -> Iterator[None]:
    """Name ``where`` (the file and table, or the option) in an :class:`InputError` raised in
    the block by a profile's or the base's own checks."""
    try:
        yield
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def profile_name(text: str) -> str:
    """The ``NAME`` of the command line's ``NAME[:key=value,…]``."""
    return text.partition(":")[0].strip()


def parse_profile(text: str) -> HullProfile:
    """A profile from the command line's ``NAME[:key=value,…]``.

    Raises:
        InputError: Malformed text, an unknown profile or key, a value that is not a number.
    """
    rest = text.partition(":")[2]
    values = {}
    for item in filter(None, (part.strip() for part in rest.split(","))):
        key, equals, value = item.partition("=")
        if not equals:
            raise InputError(f"base profile {text!r}: parameters are key=value, got {item!r}")
        if key.strip() in values:
            raise InputError(f"base profile {text!r}: {key.strip()} is given twice")
        try:
            values[key.strip()] = float(value)
        except ValueError:
            raise InputError(
                f"base profile {text!r}: {key.strip()} must be a number, got {value!r}"
            ) from None
    return make_profile(profile_name(text), values, "base profile")


def read_hull_table(path: str | Path) -> HullTable:
    """Read a hull motion table (module docstring).

    Raises:
        InputError: A missing or malformed file, an unknown column, a channel given both in
            radians and in degrees, too few rows to differentiate, a value past a plausible
            limit (:class:`~feeder.chain.model.hull_table.HullTable`), rates that contradict
            their values (:func:`_check_given_rates`).
    """
    path, header, columns = read_columns(path, "the hull motion file")
    t = columns.pop("t")
    known = {
        f"{prefix}{channel}{suffix}"
        for channel in CHANNELS
        for prefix in ("", "v_", "a_")
        for suffix in (("", "_deg") if channel in CHANNELS[3:] else ("",))
    }
    for name in header:
        if name != "t" and name not in known:
            raise InputError(
                f"{path}: unknown column {name!r}; a hull table has t and "
                f"{', '.join(CHANNELS)} [m, rad] (or roll_deg …), v_… and a_… for their rates"
            )
    values = np.zeros((t.size, 18))
    names = list(COLUMNS)  # as given, for messages
    for k, channel in enumerate(CHANNELS):
        for level, prefix in enumerate(("", "v_", "a_")):
            plain, degrees = f"{prefix}{channel}", f"{prefix}{channel}_deg"
            if plain in columns and degrees in columns:
                raise InputError(f"{path}: {plain!r} and {degrees!r} both given: keep one")
            if plain in columns:
                values[:, 6 * level + k] = columns[plain]
            elif degrees in columns:
                values[:, 6 * level + k] = np.radians(columns[degrees])
                names[6 * level + k] = degrees
            elif level and any(
                name in columns for name in (channel, f"{channel}_deg")
            ):  # a rate left out of a given channel: differentiated
                if t.size < 3:
                    raise InputError(
                        f"{path}: the rates of {channel!r} are differentiated from its values, "
                        "which needs at least 3 rows"
                    )
                values[:, 6 * level + k] = np.gradient(
                    values[:, 6 * (level - 1) + k], t, edge_order=2
                )
                names[6 * level + k] = f"{plain} (differentiated)"
    table = HullTable(Table(t, values, source=f"hull motion {path.name}"), tuple(names))
    for channel in CHANNELS:
        _check_given_rates(path, t, columns, channel)
    return table


def _check_given_rates(
    path: Path, t: np.ndarray, columns: dict[str, np.ndarray], channel: str
) -> None:
    """:func:`~feeder.chain.readers.motion_table.check_rates` on the rate columns a hull table
    gives for ``channel``, as written (radians or degrees): ``v_`` against the values, ``a_``
    against ``v_`` or, without it, the values; a rate without the column below it is not
    checked."""
    given = {}  # level → (column, name, unit [rad or m])
    for level, prefix in enumerate(("", "v_", "a_")):
        for name, unit in ((f"{prefix}{channel}", 1.0), (f"{prefix}{channel}_deg", math.pi / 180)):
            if name in columns:
                given[level] = (columns[name], name, unit)
    for level in (1, 2):
        below = level - 1 if level - 1 in given else level - 2
        if level in given and below in given:
            value, value_name, value_unit = given[below]
            rate, rate_name, rate_unit = given[level]
            check_rates(
                path,
                t,
                (value, value_name),
                (rate, rate_name),
                order=level - below,
                unit=rate_unit / value_unit,
            )


def read_base(
    table: object,
    folder: Path,
    where: str,
    forward: tuple[float, float, float] | None = None,
) -> BaseMotion:
    """The ``[base]`` table of a mechanism file (module docstring); paths relative to
    ``folder``.

    Args:
        forward: The vehicle's forward axis when the caller fixes it (the built-in device's):
            then the table may not give one. None: the table's, default the model's x.

    Raises:
        InputError: Not a table, an unknown key, a bad value (named), a forward axis where the
            caller fixes it.
    """
    if not isinstance(table, dict):
        raise InputError(f"{where}: [base] must be a table")
    if forward is not None and "forward" in table:
        raise InputError(
            f"{where}: the device's forward axis is fixed ({list(forward)}): leave forward out "
            "of [base]"
        )
    unknown = sorted(set(table) - BASE_KEYS)
    if unknown:
        raise InputError(f"{where}: unknown keys {unknown} in [base]; keys: {sorted(BASE_KEYS)}")
    profiles: list[HullProfile] = []
    if "pitch_deg" in table or "roll_deg" in table:
        pitch = check_number(f"{where} pitch_deg", table.get("pitch_deg", 0.0))
        roll = check_number(f"{where} roll_deg", table.get("roll_deg", 0.0))
        with _within(f"{where} [base]"):
            profiles.append(Slope(math.radians(pitch), math.radians(roll)))
    if "table" in table:
        if not isinstance(table["table"], str):
            raise InputError(f"{where}: [base] table must be a file name, got {table['table']!r}")
        profiles.append(read_hull_table(folder / table["table"]))
    entries = table.get("profile", [])
    if not isinstance(entries, list):
        raise InputError(f"{where}: [[base.profile]] must be a list of tables")
    for i, entry in enumerate(entries):
        here = f"{where} [[base.profile]] #{i + 1}"
        if not isinstance(entry, dict) or "type" not in entry:
            raise InputError(f"{here}: a table with a type: one of {sorted(PROFILES)}")
        values = {key: value for key, value in entry.items() if key != "type"}
        profiles.append(make_profile(entry["type"], values, here))
    if forward is None:
        forward = table.get("forward", [1.0, 0.0, 0.0])
        if not isinstance(forward, list) or len(forward) != 3:
            raise InputError(f"{where}: [base] forward must be 3 numbers, got {forward!r}")
    forward = tuple(check_finite(f"{where} forward", forward))
    with _within(f"{where} [base]"):
        return BaseMotion(tuple(profiles), forward)


def read_base_file(
    path: str | Path, forward: tuple[float, float, float] | None = None
) -> BaseMotion:
    """The ``[base]`` table of a TOML file (:func:`read_base`; paths relative to the file).

    Raises:
        InputError: A missing or unreadable file, no ``[base]`` table, any error of
            :func:`read_base`.
    """
    path = check_file("base file", path)
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"{path}: not a readable TOML file: {exc}") from exc
    if "base" not in document:
        raise InputError(f"{path}: no [base] table")
    return read_base(document["base"], path.parent, str(path), forward)
