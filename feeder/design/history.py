"""The convergence history of ``feeder design optimize`` (``history.csv``): one row per point
the search records, written again after each, and read back to resume an interrupted run.

Columns: ``iteration`` (0, 1, … over the whole run, resumed runs included); ``stage``
(``reference``: the device as given; ``sample``: a point of the global start; ``local``: an
iterate of SLSQP; ``resumed``: the point a resumed run starts from); ``objective`` [the
objective's unit, empty when the cycles failed]; ``max_violation`` [-] (the largest scaled
violation of a constraint, :mod:`feeder.design.constraints`; 0 when all are met);
``feasible`` (1 or 0); ``cycles`` (cycles run so far); ``seconds`` (wall time so far); then
each variable [its unit].
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..exceptions import InputError
from .tables import write_rows

HISTORY = "history.csv"
COLUMNS = ("iteration", "stage", "objective", "max_violation", "feasible", "cycles", "seconds")
STAGES = ("reference", "sample", "local", "resumed")


@dataclass(frozen=True)
class Iterate:
    """One row of the history (module docstring).

    Attributes:
        iteration: Its number.
        stage: ``reference``, ``sample``, ``local`` or ``resumed``.
        x: The variables [their units], (n,).
        objective: The objective [its unit]; NaN when the cycles failed.
        violation: The largest scaled violation [-].
        feasible: Every constraint met.
        cycles: Cycles run so far.
        seconds: Wall time so far [s].
    """

    iteration: int
    stage: str
    x: np.ndarray
    objective: float
    violation: float
    feasible: bool
    cycles: int
    seconds: float


class History:
    """The rows so far, and where each new one is written.

    Args:
        names: The variables' names, in order.
        rows: Rows of an earlier run (resumed), or none.
        save: Called with the history after each new row (writes ``history.csv``); None: kept
            in memory only.
    """

    def __init__(
        self,
        names: Sequence[str],
        rows: Sequence[Iterate] = (),
        save: Callable[[History], object] | None = None,
    ):
        self.names = tuple(names)
        self.rows = list(rows)
        self.save = save
        self.earlier = (rows[-1].cycles, rows[-1].seconds) if rows else (0, 0.0)

    def record(self, stage: str, x, objective, violation, feasible, cycles, seconds) -> Iterate:
        """Append a row (cycles and seconds of this run; the earlier run's are added)."""
        row = Iterate(
            len(self.rows),
            stage,
            np.array(x, dtype=float),
            float(objective),
            float(violation),
            bool(feasible),
            int(cycles) + self.earlier[0],
            float(seconds) + self.earlier[1],
        )
        self.rows.append(row)
        if self.save is not None:
            self.save(self)
        return row

    def text_rows(self) -> list[list[str]]:
        """The header and every row as text (floats as their shortest repr)."""
        rows = [[*COLUMNS, *self.names]]
        for r in self.rows:
            number = "" if not math.isfinite(r.objective) else repr(r.objective)
            rows.append(
                [str(r.iteration), r.stage, number, repr(r.violation), str(int(r.feasible)),
                 str(r.cycles), f"{r.seconds:.3f}", *(repr(float(v)) for v in r.x)]
            )  # fmt: skip
        return rows

    def write(self, path: str | Path) -> Path:
        """Write ``history.csv`` at ``path``, atomically."""
        return write_rows(path, self.text_rows())


def read_history(path: str | Path, names: Sequence[str]) -> list[Iterate]:
    """The rows of an earlier run's ``history.csv`` for the variables ``names``.

    Raises:
        InputError: Not a history of these variables, or a cell that does not read back.
    """
    path = Path(path)
    try:
        with path.open(encoding="utf-8", newline="") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {path}: {exc}") from exc
    if not lines or tuple(lines[0]) != (*COLUMNS, *names):
        raise InputError(
            f"{path} is not the history of these variables ({', '.join(names)}): write to "
            "another folder, or delete it to start afresh"
        )
    rows = []
    for number, cells in enumerate(lines[1:], start=2):
        try:
            if len(cells) != len(lines[0]) or cells[1] not in STAGES:
                raise ValueError("wrong cells")
            rows.append(
                Iterate(
                    int(cells[0]),
                    cells[1],
                    np.array([float(c) for c in cells[len(COLUMNS) :]]),
                    float(cells[2]) if cells[2] else math.nan,
                    float(cells[3]),
                    cells[4] == "1",
                    int(cells[5]),
                    float(cells[6]),
                )
            )
        except ValueError as exc:
            raise InputError(
                f"{path}, line {number}: not a history row ({exc}): delete it to start afresh"
            ) from exc
    return rows
