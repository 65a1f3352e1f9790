"""The design file of a mechanism (TOML, beside its mechanism file): the design variables and
their bounds, the objective, the constraints and the search's settings, for
``feeder design sensitivities MODEL --design FILE`` and ``feeder design optimize MODEL --design
FILE``::

    [variables]              # each {lower, upper, start (default: the model's value)}
    cylinder_pivot.x = {lower = 0.9, upper = 1.5}   # [m] x of a joint's <origin xyz>
    body_pin.y = {lower = -0.3, upper = -0.1}       # [m] a frame (a link) moved through the
                                                    #     origin of the joint that carries it
    # body.mass = {lower = 2500, upper = 3500}      # [kg] a body's mass, its inertia with it
    # body.scale = {lower = 0.9, upper = 1.1}       # [-] a body's length scale
    # joint.roll / .pitch / .yaw                    # [rad] of <origin rpy>

    [objective]
    peak = "tau_cylinder_slide"          # the largest |value| over every motion table's samples
    # weighted = {tau_cylinder_slide = 1.0, body_hinge_force = 0.5}   # Σ W · peak / reference

    [constraints]            # every sample of every motion assembles: always required
    stroke = {cylinder_slide = {min = 0.75, max = 2.0}}   # [m or rad] the joint's coordinate
    # max_velocity_gain = 10.0             # distance to a singular pose (the gain → ∞ there)

    [limits]                 # largest |value| allowed of other peaks [their SI unit]
    # body_hinge_force = 60000.0

    [search]                 # feeder design optimize only
    samples = 0              # Latin-hypercube points of the global start (0: start at the model)
    starts = 1               # local searches (SLSQP) from the best points

The peaks are named as the columns of ``feeder analyze``'s ``loads.csv``: ``tau_<joint>`` (the
drive load of an actuated joint [N or N·m]), ``<joint>_force``, ``<joint>_moment`` (a joint's
reaction magnitudes), ``<element>_force`` (a force element's force), ``<closure>_force``,
``<closure>_moment`` (a closure's force and moment magnitudes, from its x, y, z columns) and
``velocity_gain`` (:mod:`~feeder.design.mechanism.evaluation`).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

from ...exceptions import InputError
from ...validation import check_number, did_you_mean
from ..design_space import Variable, design_text, table_of
from ..differentiable import DesignParameter
from ..objectives import Objective, Term
from .urdf_edit import COMPONENTS, Target, carrier, names, parse, value

KEYS = ("variables", "objective", "constraints", "limits", "search")
CONSTRAINT_KEYS = ("assembly", "stroke", "max_velocity_gain")
SEARCH_KEYS = ("samples", "starts")
ATTRIBUTES = (*COMPONENTS, "mass", "scale")
"""What a variable may name after the dot: an origin's component, a body's mass or scale."""


@dataclass(frozen=True)
class MechanismVariable(Variable):
    """One design variable of a mechanism: the device's
    :class:`~feeder.design.design_space.Variable` (its name, unit and meaning, bounds, start;
    ``loads`` always True: every variable may move a load) and what it changes in the URDF.

    Attributes:
        target: What it changes in the URDF.
    """

    target: Target


@dataclass(frozen=True)
class Stroke:
    """A joint's coordinate kept within [low, high] over every sample [m or rad]."""

    joint: str
    low: float
    high: float


@dataclass(frozen=True)
class MechanismDesign:
    """A mechanism's design file, checked against its URDF (its peaks' names are checked
    against a run, :func:`check_peaks`).

    Attributes:
        path: The file.
        variables: The variables, in the file's order.
        objective: What is minimised (:class:`~feeder.design.objectives.Objective`, its terms'
            quantities the peaks' names).
        strokes: Coordinate ranges to keep.
        max_gain: Largest velocity gain allowed, or None.
        limits: Peak name → the largest |value| allowed [its SI unit].
        samples, starts: The search's settings.
        text: The file's text (for the manifest's hash).
    """

    path: Path
    variables: tuple[MechanismVariable, ...]
    objective: Objective
    strokes: tuple[Stroke, ...]
    max_gain: float | None
    limits: dict[str, float]
    samples: int
    starts: int
    text: str


def _unknown(where: str, found, allowed) -> None:
    if unknown := sorted(set(found) - set(allowed)):
        raise InputError(f"{where}: unknown key {unknown[0]!r}; keys: {', '.join(allowed)}")


def _entries(where: str, table: dict) -> list[tuple[str, object]]:
    """``joint.x = {…}`` (TOML's dotted key: a table ``joint`` holding ``x``) or ``"joint.x" =
    {…}``, flattened to (name, entry)."""
    found = []
    for key, entry in table.items():
        if isinstance(entry, dict) and not {"lower", "upper"} & set(entry):
            found += [(f"{key}.{attribute}", sub) for attribute, sub in entry.items()]
        else:
            found.append((key, entry))
    return found


def _target(where: str, name: str, root) -> Target:
    joints, links = names(root)
    owner, dot, attribute = name.rpartition(".")
    if not dot or attribute not in ATTRIBUTES:
        raise InputError(
            f"{where}: [variables] {name!r} must be NAME.ATTRIBUTE, ATTRIBUTE one of "
            f"{', '.join(ATTRIBUTES)}"
        )
    if attribute in ("mass", "scale"):
        if owner not in links:
            hint = did_you_mean(owner, links)
            raise InputError(
                f"{where}: [variables] {name}: no link {owner!r} in the model; {hint}links: "
                f"{', '.join(links)}"
            )
        if attribute == "mass" and value(root, Target("mass", owner)) <= 0.0:
            raise InputError(f"{where}: [variables] {name}: the link {owner!r} has no mass")
        return Target(attribute, owner)
    joint = owner if owner in joints else carrier(root, owner) if owner in links else None
    if joint is None:
        hint = did_you_mean(owner, [*joints, *links])
        raise InputError(
            f"{where}: [variables] {name}: no joint or frame {owner!r} in the model (or it is the "
            f"root link); {hint}joints: {', '.join(joints)}"
        )
    return Target("origin", joint, attribute)


def _variable(where: str, name: str, entry: object, root) -> MechanismVariable:
    target = _target(where, name, root)
    here = f"{where}: [variables] {name}"
    if not isinstance(entry, dict) or not {"lower", "upper"} <= set(entry):
        raise InputError(f"{here} must be {{lower = …, upper = …}} [{target.unit}], got {entry!r}")
    _unknown(here, entry, ("lower", "upper", "start"))
    lower = check_number(f"{here} lower [{target.unit}]", entry["lower"])
    upper = check_number(f"{here} upper [{target.unit}]", entry["upper"])
    if not lower < upper:
        raise InputError(f"{here}: lower {lower:g} must be below upper {upper:g} {target.unit}")
    if target.kind == "scale" and lower <= 0.0:
        raise InputError(f"{here}: a length scale's lower bound must be positive, got {lower:g}")
    if target.kind == "mass" and lower <= 0.0:
        raise InputError(f"{here}: a mass's lower bound must be positive, got {lower:g} kg")
    start = check_number(f"{here} start [{target.unit}]", entry.get("start", value(root, target)))
    if not lower <= start <= upper:
        raise InputError(
            f"{here}: start {start:g} is outside [{lower:g}, {upper:g}] {target.unit}"
        )
    meaning = {
        "origin": f"{target.component} of the origin of joint {target.name}",
        "mass": f"mass of {target.name} (inertia scaled with it)",
        "scale": f"length scale of {target.name}",
    }[target.kind]
    parameter = DesignParameter(name, target.unit, meaning)
    return MechanismVariable(parameter, lower, upper, start, True, target)


def _weight(where: str, name: str, value: object) -> float:
    number = check_number(f"{where}: [objective] weighted {name}", value)
    if number <= 0.0:
        raise InputError(f"{where}: [objective] weighted {name}: weights must be positive")
    return number


def _objective(where: str, table: dict) -> Objective:
    _unknown(f"{where}: [objective]", table, ("peak", "weighted"))
    if ("peak" in table) == ("weighted" in table):
        raise InputError(f'{where}: [objective] needs peak = "NAME" or weighted = {{NAME = W}}')
    if "peak" in table:
        name = table["peak"]
        if not isinstance(name, str) or not name:
            raise InputError(f"{where}: [objective] peak must be a peak's name, got {name!r}")
        return Objective(name, (Term(name, (name,), 1.0),), weighted=False)
    weights = table["weighted"]
    if not isinstance(weights, dict) or not weights:
        raise InputError(f"{where}: [objective] weighted must be {{NAME = W, …}}, got {weights!r}")
    terms = tuple(Term(n, (n,), _weight(where, n, w)) for n, w in weights.items())
    text = "weighted:" + ",".join(f"{t.name}={t.weight:g}" for t in terms)
    return Objective(text, terms, weighted=True)


def _strokes(where: str, table: object, joints: list[str]) -> tuple[Stroke, ...]:
    if not isinstance(table, dict):
        raise InputError(f"{where}: [constraints] stroke must be {{joint = {{min, max}}}}")
    strokes = []
    for joint, entry in table.items():
        here = f"{where}: [constraints] stroke {joint}"
        if joint not in joints:
            hint = did_you_mean(joint, joints)
            raise InputError(
                f"{here}: no joint {joint!r} in the model; {hint}joints: {', '.join(joints)}"
            )
        if not isinstance(entry, dict) or set(entry) != {"min", "max"}:
            raise InputError(f"{here} must be {{min = …, max = …}} [m or rad], got {entry!r}")
        low = check_number(f"{here} min", entry["min"])
        high = check_number(f"{here} max", entry["max"])
        if not low < high:
            raise InputError(f"{here}: min {low:g} must be below max {high:g}")
        strokes.append(Stroke(joint, low, high))
    return tuple(strokes)


def _count(where: str, key: str, value: object, least: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise InputError(
            f"{where}: [search] {key} must be a whole number ≥ {least}, got {value!r}"
        )
    return value


def mechanism_design(text: str, urdf: str, where: str, urdf_where: str) -> MechanismDesign:
    """The design of the TOML ``text`` for the model ``urdf`` (its text), checked (the peaks'
    names are checked by :func:`check_peaks`, against a run).

    Raises:
        InputError: Not TOML; an unknown table or key; a variable naming no joint, frame or
            link (close matches named), or an attribute it cannot have; bounds that are not
            numbers, lower ≥ upper, a start outside them; no variable; no objective; a stroke
            on no joint or with min ≥ max; a gain limit or a limit ≤ 0; a bad count.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where} is not a TOML design file: {exc}") from exc
    _unknown(where, data, KEYS)
    root = parse(urdf, urdf_where)
    entries = _entries(where, table_of(where, data, "variables"))
    if not entries:
        raise InputError(f"{where}: [variables] is empty: name at least one variable")
    variables = tuple(_variable(where, name, entry, root) for name, entry in entries)
    if len({v.name for v in variables}) != len(variables):
        raise InputError(f"{where}: [variables] names a variable twice")
    objective = _objective(where, table_of(where, data, "objective"))
    constraints = table_of(where, data, "constraints")
    _unknown(f"{where}: [constraints]", constraints, CONSTRAINT_KEYS)
    if constraints.get("assembly", True) is not True:
        raise InputError(f"{where}: [constraints] assembly is always required: remove the key")
    strokes = _strokes(where, constraints.get("stroke", {}), names(root)[0])
    gain = constraints.get("max_velocity_gain")
    if gain is not None:
        gain = check_number(f"{where}: [constraints] max_velocity_gain", gain)
        if gain <= 0.0:
            raise InputError(f"{where}: [constraints] max_velocity_gain must be positive")
    limits = {}
    for name, limit in table_of(where, data, "limits").items():
        limits[name] = check_number(f"{where}: [limits] {name}", limit)
        if limits[name] <= 0.0:
            raise InputError(f"{where}: [limits] {name} must be positive, got {limit!r}")
    search = table_of(where, data, "search")
    _unknown(f"{where}: [search]", search, SEARCH_KEYS)
    samples = _count(where, "samples", search.get("samples", 0), 0)
    starts = _count(where, "starts", search.get("starts", 1), 1)
    return MechanismDesign(
        Path(where), variables, objective, strokes, gain, limits, samples, starts, text
    )


def check_peaks(design: MechanismDesign, available: dict[str, str]) -> None:
    """Refuse an objective term or a limit that names no peak of the mechanism (``available``:
    peak name → unit, from a run), naming the close match and the peaks there are.

    Raises:
        InputError: One line, with the file and the key.
    """
    for key, name in [("objective", n) for n in design.objective.quantities()] + [
        ("limits", n) for n in design.limits
    ]:
        if name not in available:
            hint = did_you_mean(name, available)
            raise InputError(
                f"{design.path}: [{key}] {name!r} names no load of the mechanism; {hint}peaks: "
                f"{', '.join(available)}"
            )


def read_mechanism_design(path: str | Path, urdf: str, urdf_where: str) -> MechanismDesign:
    """The design file ``path`` for the model ``urdf`` (its text), checked
    (:func:`mechanism_design`)."""
    return mechanism_design(design_text(path), urdf, str(path), urdf_where)
