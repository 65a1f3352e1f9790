"""The parameters of a device that the design commands differentiate: its lengths [m] and link
masses [kg], chosen from the field metadata of
:class:`~feeder.device.parameters.FeederParameters`, and the parameter set with one of them
changed.

Chosen: every field whose unit is ``m`` (the loop geometry L1, L2, d3, …, the forearm and
payload offsets c, d, e, f, e5, h5, z5, the drives' bore and rod diameters and pinion radius),
except those in :data:`LEFT_OUT`, and the mass of every link (``cylinder.mass``, …,
``payload.mass``). Left out: names, every angle (``phi3_load``, ``swing`` define the motion;
the elevation, φ1, φ3, φ4 bounds are limits), the piston's end stops ``r2_min``, ``r2_max``
(limits: a load does not depend on them while the cycle stays inside), the payload's drawn
size (:data:`LEFT_OUT`), and the links' moments of inertia (Table I's are below 0.04 kg·m²,
against 18 kg·m² of the payload's m·r² about the arm pivot).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

from ..device.parameters import FeederParameters
from ..exceptions import InputError

LEFT_OUT = {
    "r2_min": "a limit: the piston's end stop",
    "r2_max": "a limit: the piston's end stop",
    "payload_length": "drawn only (URDF visual and figures): no load depends on it",
    "payload_diameter": "drawn only (URDF visual and figures): no load depends on it",
}
"""Length fields [m] that are not differentiated, with the reason."""

SCALES = {"m": 0.1, "kg": 1.0, "rad": 0.1, "-": 1.0}
"""The smallest magnitude [unit] a step is taken relative to (:func:`~.differences.step`): a
length near zero (the offset c = −0.014 m, a position L2) is stepped as if it were 0.1 m, the
size of the device's links, so that its step does not vanish with its value. A mechanism's
design variables (:mod:`feeder.design.mechanism`) also have angles of a joint's origin [rad],
stepped as if at least 0.1 rad, and length scales [-], whose value 1 is their scale."""


@dataclass(frozen=True)
class DesignParameter:
    """One differentiable number of a parameter set.

    Attributes:
        name: The field's name (``L1``), or ``link.mass`` for a link's mass (``payload.mass``):
            the parameter file's spelling.
        unit: ``m`` or ``kg``.
        meaning: The field's source text (what the number is).
    """

    name: str
    unit: str
    meaning: str

    @property
    def scale(self) -> float:
        """The smallest magnitude a step is taken relative to [unit] (:data:`SCALES`)."""
        return SCALES[self.unit]

    def value(self, params: FeederParameters) -> float:
        """The parameter's value in ``params`` [unit]."""
        field, _, part = self.name.partition(".")
        value = getattr(params, field)
        return float(value.mass) if part else float(value)

    def changed(self, params: FeederParameters, value: float) -> FeederParameters:
        """``params`` with this parameter set to ``value`` [unit] (everything else kept: a mass
        keeps its link's moments of inertia)."""
        field, _, part = self.name.partition(".")
        if part:
            return replace(params, **{field: replace(getattr(params, field), mass=value)})
        return replace(params, **{field: value})


def design_parameters() -> tuple[DesignParameter, ...]:
    """Every differentiable parameter (module docstring), lengths in field order, then the
    link masses."""
    lengths, masses = [], []
    for field in fields(FeederParameters):
        if field.type == "LinkInertia":
            masses.append(DesignParameter(f"{field.name}.mass", "kg", f"mass of the {field.name}"))
        elif field.metadata.get("unit") == "m" and field.name not in LEFT_OUT:
            lengths.append(DesignParameter(field.name, "m", field.metadata["source"]))
    return tuple(lengths + masses)


def chosen_parameters(names: list[str] | tuple[str, ...] | None) -> tuple[DesignParameter, ...]:
    """The parameters named ``names`` in the given order, or all of them for None.

    Raises:
        InputError: An unknown or repeated name, or an empty list.
    """
    available = {parameter.name: parameter for parameter in design_parameters()}
    if names is None:
        return tuple(available.values())
    if isinstance(names, str) or len(names) == 0:
        raise InputError(f"parameters must be a non-empty list of names, got {names!r}")
    for name in names:
        if name not in available:
            why = why_not(name)
            raise InputError(
                f"parameter {name!r} is not differentiable ({why}); choose from "
                f"{', '.join(available)}"
            )
    if len(set(names)) != len(names):
        raise InputError(f"parameters must not repeat a name, got {list(names)}")
    return tuple(available[name] for name in names)


def why_not(name: object, verb: str = "differentiate") -> str:
    """Why ``name`` is not a parameter of the design commands, for their messages: its
    :data:`LEFT_OUT` reason, or what its field is (a link: ``verb`` its mass instead; an angle;
    not a number), or that there is no such parameter."""
    if not isinstance(name, str):
        return "no such parameter"
    if name in LEFT_OUT:
        return LEFT_OUT[name]
    field = {f.name: f for f in fields(FeederParameters)}.get(name)
    if field is None:
        return "no such parameter"
    if field.type == "LinkInertia":
        return f"a link: {verb} its mass, {name}.mass"
    unit = field.metadata.get("unit")
    if unit == "rad":
        return "an angle: a motion definition or a limit"
    return "not a number" if not unit else f"unit {unit}"
