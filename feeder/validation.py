"""Checks at the boundaries: the public API, the command line and the file readers.

Every function here returns the value converted to what the internals expect (a float, a float
array of a known shape, an int array of 0/1 flags) or raises an
:class:`~feeder.exceptions.InputError` that names the value and shows it. Internals trust what
has passed through here and do not check again. This module imports nothing from feeder but
its exceptions, so every layer may use it.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from .exceptions import ElevationError, FeederError, InputError

LIMIT_SLACK = 1e-12
"""Rounding slack [rad or m] when a value is compared with a range's ends: a limit computed by
a formula may differ from the same limit typed in by a few ulps."""


def check_finite(name: str, value: float | Iterable[float] | np.ndarray) -> np.ndarray:
    """Return ``value`` as a float array, or raise :class:`InputError` if it is not numeric or any
    entry is NaN/inf.

    Text is refused even where numpy would parse it (``"0.5"``), and so are truth values
    (``True`` is not 1 m): each is a mistake of the caller's, not a number.

    Args:
        name: What the value is, for the message.
        value: Scalar or array-like.
    """
    if isinstance(value, str | bytes):
        raise InputError(f"{name} must be numeric, got the text {value!r}")
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric, got {value!r}") from exc
    kind = np.asarray(value).dtype.kind
    if kind in "USO" and array.size:
        raise InputError(f"{name} must be numeric, got {value!r}")
    if kind == "b":
        raise InputError(f"{name} must be numeric, got the truth value(s) {value!r}")
    if not np.all(np.isfinite(array)):
        bad = float(array.flat[int(np.argmin(np.isfinite(array).ravel()))])
        raise InputError(f"{name} must be finite, got {bad}")
    return array


def check_number(name: str, value: float) -> float:
    """Return ``value`` as a float if it is one finite real number (not a bool, not text)."""
    if isinstance(value, bool | np.bool_):
        raise InputError(f"{name} must be a number, got the truth value {value!r}")
    array = check_finite(name, value)
    if array.shape != ():
        raise InputError(f"{name} must be one number, got {value!r}")
    return float(array)


def check_elevation(elevation: float, limits: tuple[float, float]) -> float:
    """Return the elevation [rad] if it is one finite number inside ``limits`` [rad], else raise.

    Raises:
        InputError: NaN, infinite, non-scalar, text or truth-value elevation.
        ElevationError: Elevation outside the range.
    """
    eps = check_number("elevation [rad]", elevation)
    low, high = limits
    if not low - LIMIT_SLACK <= eps <= high + LIMIT_SLACK:
        raise ElevationError(
            f"elevation {math.degrees(eps):.7g}° is outside the device's range "
            f"[{math.degrees(low):.7g}°, {math.degrees(high):.7g}°]"
        )
    return eps


def check_elevations_deg(
    values: float | Iterable[float] | np.ndarray, limits: tuple[float, float] | None
) -> list[float]:
    """Return the elevations [deg] as a list of floats, at least one, each a finite number (not
    text nor a truth value) and, unless ``limits`` is None, inside ``limits`` [rad].

    Raises:
        InputError: An entry that is not one finite number; no entry.
        ElevationError: An elevation outside the range.
    """
    entries = np.ravel(np.asarray(values, dtype=object))  # objects: text stays text, True True
    elevations = [check_number("elevation [deg]", e) for e in entries]
    if not elevations:
        raise InputError("the elevations are empty: at least one elevation is needed")
    if limits is not None:
        for e in elevations:
            check_elevation(math.radians(e), limits)
    return elevations


def check_vector(name: str, value: np.ndarray, size: int) -> np.ndarray:
    """``value`` as a finite float array of shape (size,)."""
    array = check_finite(name, value)
    if array.shape != (size,):
        raise InputError(f"{name} must have shape ({size},), got {array.shape}")
    return array


def check_samples(name: str, value: np.ndarray, width: int, what: str = "") -> np.ndarray:
    """``value`` as a finite float array of shape (N, width), N ≥ 1.

    Args:
        name: What the value is, for the message.
        value: Array-like.
        width: Number of columns.
        what: What the columns are, for the message (e.g. "[φ1, r2, φ3, φ4]").
    """
    array = check_finite(name, value)
    if array.ndim != 2 or array.shape[1] != width or array.shape[0] == 0:
        columns = f" = {what}" if what else ""
        raise InputError(f"{name} must have shape (N, {width}){columns}, N ≥ 1, got {array.shape}")
    return array


def check_flags(name: str, value: np.ndarray, count: int) -> np.ndarray:
    """``value`` as an int array of shape (count,) whose entries are 0 or 1."""
    flags = check_finite(name, value)
    if flags.shape != (count,):
        raise InputError(f"{name} must have shape ({count},), got {flags.shape}")
    if not np.all((flags == 0) | (flags == 1)):
        raise InputError(f"{name} must be 0 or 1, got {np.unique(flags)}")
    return flags.astype(int)


def check_path(name: str, value: str | os.PathLike) -> Path:
    """``value`` as a Path if it names a file or folder: text or a path, not empty nor blank
    (an empty path would silently mean the current folder)."""
    if not isinstance(value, str | os.PathLike):
        raise InputError(f"{name} must be a path, got {value!r}")
    if not str(value).strip():
        raise InputError(f"{name} must name a file or folder, got an empty path")
    return Path(value)


def check_file(name: str, value: str | os.PathLike, error: type[FeederError] = InputError) -> Path:
    """``value`` as a Path (:func:`check_path`) if it names an existing file; else ``error``
    (default :class:`InputError`) saying that ``name`` is not found there, or is a folder (a
    folder read as a file would be reported as missing, or fail deep inside a reader)."""
    path = check_path(name, value)
    if path.is_dir():
        raise error(f"{name} {path} is a folder, not a file")
    if not path.is_file():
        raise error(f"{name} not found: {path}")
    return path


def first_outside(values: np.ndarray, low: float, high: float) -> int | None:
    """Flat index of the first value outside [low, high] (with :data:`LIMIT_SLACK`), or None."""
    values = np.ravel(values)
    outside = np.flatnonzero((values < low - LIMIT_SLACK) | (values > high + LIMIT_SLACK))
    return int(outside[0]) if outside.size else None


def did_you_mean(name: str, names: Iterable[str]) -> str:
    """``"did you mean 'X'? "`` for the one of ``names`` closest to a misspelt ``name``
    (:func:`difflib.get_close_matches`), or ``""`` when none is close: the hint of a refusal."""
    near = difflib.get_close_matches(name, list(names), n=1)
    return f"did you mean {near[0]!r}? " if near else ""
