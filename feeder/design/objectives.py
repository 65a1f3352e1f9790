"""What ``feeder design optimize`` minimises: the peak of one quantity over every elevation and
vehicle case, or a weighted sum of such peaks (``--objective``).

* ``peak_pressure``: the cylinder's working pressure, the larger of the cap-end and rod-end
  chambers' peaks [Pa] (what rates the cylinder);
* ``peak_piston_force`` [N], ``peak_forearm_moment`` [N·m]: the two drives' loads;
* any peak of ``sweep_peaks.csv`` by its name (:data:`~feeder.study.sweep_table.QUANTITIES`:
  ``arm_frame_force``, ``rack_force``, …), in its SI unit;
* ``weighted:NAME=W,NAME=W,…``: Σ W · (the peak of NAME) / (its value for the device as given),
  each NAME one of the above and each W > 0: a sum of ratios, without unit.

A term's peak is the largest magnitude over its quantities, the samples of each cycle, the
elevations and the cases.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..exceptions import InputError
from ..study.elevation_sweeps import UNITS
from ..study.sweep_table import QUANTITIES
from ..validation import check_number, did_you_mean

ALIASES: dict[str, tuple[str, ...]] = {
    "peak_pressure": ("cylinder_cap_pressure", "cylinder_rod_pressure"),
    "peak_piston_force": ("piston_force",),
    "peak_forearm_moment": ("forearm_torque",),
}
"""The objectives named for the drives, and the quantities whose largest peak each is."""

WEIGHTED = "weighted:"


@dataclass(frozen=True)
class Term:
    """One peak of the objective.

    Attributes:
        name: As given (``peak_pressure``, ``arm_frame_force``).
        quantities: The sweep's quantities whose largest magnitude it is.
        weight: Its weight [-] (1 for a single peak).
    """

    name: str
    quantities: tuple[str, ...]
    weight: float

    @property
    def unit(self) -> str:
        """The peak's SI unit."""
        return UNITS[self.quantities[0]]


@dataclass(frozen=True)
class Objective:
    """The objective: one term, or a weighted sum of terms relative to the device as given.

    Attributes:
        text: As given on the command line.
        terms: The peaks.
        weighted: A weighted sum (its value is Σ W · peak / reference, unit "").
    """

    text: str
    terms: tuple[Term, ...]
    weighted: bool

    @property
    def unit(self) -> str:
        """The objective's unit: the peak's, or "" for a weighted sum."""
        return "" if self.weighted else self.terms[0].unit

    def value(self, peaks: list[float], references: list[float]) -> float:
        """The objective from each term's peak [its unit] and its reference value (the device
        as given) [its unit]."""
        if not self.weighted:
            return peaks[0]
        return sum(t.weight * p / r for t, p, r in zip(self.terms, peaks, references, strict=True))

    def quantities(self) -> tuple[str, ...]:
        """Every quantity the terms read, each once."""
        return tuple(dict.fromkeys(q for term in self.terms for q in term.quantities))


def _term(name: str, weight: float) -> Term:
    if name in ALIASES:
        return Term(name, ALIASES[name], weight)
    if name in QUANTITIES:
        return Term(name, (name,), weight)
    known = [*ALIASES, *QUANTITIES]
    hint = did_you_mean(name, known)
    raise InputError(
        f"the objective {name!r} names no peak; {hint}choose {', '.join(ALIASES)}, a peak of the "
        f"sweep ({', '.join(QUANTITIES)}) or weighted:NAME=W,…"
    )


def parse_objective(text: object) -> Objective:
    """The objective ``text`` (module docstring), checked.

    Raises:
        InputError: Not text; a name that is no peak; a weighted sum without terms, with a term
            that is not NAME=W, a weight that is not a positive number, or a repeated name.
    """
    if not isinstance(text, str) or not text:
        raise InputError(f"the objective must be a peak's name, got {text!r}")
    if not text.startswith(WEIGHTED):
        return Objective(text, (_term(text, 1.0),), weighted=False)
    terms = []
    for part in text[len(WEIGHTED) :].split(","):
        name, equals, weight = part.partition("=")
        if not equals or not name.strip():
            raise InputError(
                f"the objective {text!r}: each term of a weighted sum is NAME=WEIGHT, got {part!r}"
            )
        try:
            number = float(weight)
        except ValueError:
            number = weight
        number = check_number(f"the objective {text!r}: the weight of {name.strip()}", number)
        if number <= 0.0:
            raise InputError(f"the objective {text!r}: weights must be positive, got {part!r}")
        terms.append(_term(name.strip(), number))
    names = [term.name for term in terms]
    if len(set(names)) != len(names):
        raise InputError(f"the objective {text!r} names a peak twice")
    return Objective(text, tuple(terms), weighted=True)
