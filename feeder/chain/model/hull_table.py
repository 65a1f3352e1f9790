"""A hull's motion as a table: measured or simulated channels against time, interpolated.

A :class:`HullTable` is a profile (:mod:`feeder.chain.model.channels`) whose 18 :data:`COLUMNS`
(each channel's value, rate and acceleration) a user gives against time, e.g. from a CSV file
(:mod:`feeder.chain.readers.base_motion`). Times outside the table are refused, and so are values
past the plausible limits of :mod:`feeder.chain.model.hull`, with a hint when an angle looks like
degrees given as radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...exceptions import InputError
from .channels import Channels
from .forces import Table
from .hull import CHANNELS, beyond, implausible, limit, show, unit_of

COLUMNS = tuple(f"{prefix}{channel}" for prefix in ("", "v_", "a_") for channel in CHANNELS)
"""A hull table's 18 columns, in order: the channels' values, rates (``v_``) and accelerations
(``a_``), angles in radians."""


@dataclass(frozen=True)
class HullTable:
    """The hull's measured or simulated motion: a :class:`Table` of the 18 :data:`COLUMNS`
    against time (the units of :mod:`feeder.chain.model.channels`), linearly interpolated;
    times outside the table are refused, and so are values past the plausible limits
    (:mod:`feeder.chain.model.hull`).

    Attributes:
        table: Times t [s] (K,) and values (K, 18).
        columns: The columns' names as the user gave them, for messages (a file's ``roll_deg``,
            converted to radians in the table); default :data:`COLUMNS`.
    """

    table: Table
    columns: tuple[str, ...] = field(default=COLUMNS, compare=False)

    def __post_init__(self):
        if not isinstance(self.table, Table):
            raise InputError(
                f"a hull table is a Table (feeder.chain.model.forces: t [s], values (K, 18)), "
                f"got {self.table!r}"
            )
        if self.table.values.shape[1] != 18:
            raise InputError(
                f"{self.table.source}: a hull table has 18 columns (value, rate, acceleration "
                f"of {', '.join(CHANNELS)}), got {self.table.values.shape[1]}"
            )
        names = self.columns
        if (
            not isinstance(names, tuple)
            or len(names) != 18
            or not all(isinstance(name, str) for name in names)
        ):
            raise InputError(f"{self.table.source}: columns must be 18 names, got {names!r}")
        self._check_plausible()

    def _check_plausible(self) -> None:
        """Raise :class:`InputError` if a column passes its plausible limit: its name as given,
        the value and its time, and for an angle in radians that would be plausible in degrees,
        the column's ``_deg`` form."""
        excess = implausible(self.peaks())
        if excess is None:
            return
        level, channel = excess
        k = 6 * level + channel
        row = int(np.argmax(np.abs(self.table.values[:, k])))
        value = float(self.table.values[row, k])
        hint = ""
        degrees = abs(math.radians(value)) <= limit(level, channel)[0]
        if channel >= 3 and self.columns[k] == COLUMNS[k] and degrees:
            hint = f"; if it holds degrees, name the column {COLUMNS[k]}_deg (angles are radians)"
        raise InputError(
            f"{self.table.source}: {self.columns[k]} = {show(value, unit_of(level, channel))} at "
            f"t = {self.table.t[row]:g} s is {beyond(level, channel)}{hint}"
        )

    def channels(self, t: np.ndarray) -> Channels:
        lo, hi = self.table.t[0], self.table.t[-1]
        if t.size and (t.min() < lo or t.max() > hi):
            raise InputError(
                f"{self.table.source}: the hull motion covers t = {lo:g} … {hi:g} s; the motion "
                f"asks for {t.min():g} … {t.max():g} s"
            )
        values = np.column_stack(
            [np.interp(t, self.table.t, column) for column in self.table.values.T]
        )
        return Channels(values[:, :6], values[:, 6:12], values[:, 12:])

    def peaks(self) -> np.ndarray:
        """The peaks (:meth:`~feeder.chain.model.channels.BoundedProfile.peaks`): the largest
        |entry| of each column (the table is interpolated linearly between its rows)."""
        return np.abs(self.table.values).max(axis=0).reshape(3, 6)

    def describe(self) -> str:
        return f"hull motion table {self.table.source}"
