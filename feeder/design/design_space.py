"""The design file of ``feeder design optimize``: which parameters are free and within which
bounds, which are set for the run, the geometric constraints' settings and the limits on other
peaks (TOML; ``feeder design optimize --print-design`` prints the built-in one, :data:`BUILT_IN`).

Free parameters (``[variables]``) and set ones (``[fixed]``) are the lengths [m] and link masses
[kg] that the sensitivities differentiate (:func:`~feeder.design.differentiable.design_parameters`)
and the piston's end stops ``r2_min``, ``r2_max`` [m]: no load depends on the end stops, so as
variables they act only through the constraints (the travel inside them, the stroke), as a
cylinder to be chosen within the bounds. Every other parameter stays as the device has it.
"""

from __future__ import annotations

import difflib
import tomllib
from dataclasses import dataclass
from pathlib import Path

from ..device.loop import TRANSMISSION_BAND_DEG
from ..device.parameters import SINGULAR_TRANSMISSION_DEG, FeederParameters
from ..exceptions import FeederError, InputError
from ..study.sweep_table import QUANTITIES
from ..validation import check_number, did_you_mean
from .differentiable import DesignParameter, design_parameters, why_not

END_STOPS = {
    "r2_min": "the piston's end stop, retracted",
    "r2_max": "the piston's end stop, extended",
}
"""Variables that no load depends on (the cycle never reaches an end stop): they enter the
constraints only."""

BAND = TRANSMISSION_BAND_DEG
TOGGLE = SINGULAR_TRANSMISSION_DEG

BUILT_IN = f"""\
# The design of the feeder's geometry for `feeder design optimize --design FILE` (this text:
# `feeder design optimize --print-design`). Units: m, kg, degrees for keys ending _deg, and each
# peak's SI unit (docs/REFERENCE.md). Free parameters: the lengths and link masses that
# `feeder design sensitivities` differentiates, and the piston's end stops r2_min, r2_max.

[variables]  # lower and upper bounds; start = … (default: the device's value, moved into bounds)
L1 = {{lower = -0.60, upper = -0.38}}    # [m] arm pivot A, x from the cylinder pivot B
L2 = {{lower = 0.20, upper = 0.36}}      # [m] arm pivot A, y from B
d3 = {{lower = 0.14, upper = 0.26}}      # [m] arm lever: pivot A to the rod-eye pin
r2_min = {{lower = 0.20, upper = 0.30}}  # [m] piston end stop, retracted (the cylinder's length)
r2_max = {{lower = 0.45, upper = 0.56}}  # [m] piston end stop, extended

[fixed]  # parameters set for the whole run (default: none, the device's values)

[constraints]
transmission_band_deg = [{BAND[0]!r}, {BAND[1]!r}]  # [deg] transmission angle, all the travel
toggle_margin_deg = {TOGGLE!r}                # [deg] least distance from the toggle (at least 5)
end_stop_clearance = 0.01              # [m] the travel's r2 this far inside r2_min … r2_max
max_stroke = 0.30                      # [m] r2_max − r2_min at most: the cylinder's stroke

[limits]  # upper limits on other peaks' magnitudes over every elevation and case [SI]
# arm_frame_force = 3500.0  # [N]
"""
"""The built-in design: the cylinder's pivot position and lever, and its end stops, about ±20 %
around the projectile feeder's; its band, its 10 mm end-stop clearance and a 0.30 m stroke (the
reference cylinder's 0.298 m, rounded up)."""

CONSTRAINT_KEYS = (
    "transmission_band_deg",
    "toggle_margin_deg",
    "end_stop_clearance",
    "max_stroke",
)
KEYS = ("variables", "fixed", "constraints", "limits")


@dataclass(frozen=True)
class Variable:
    """One free parameter.

    Attributes:
        parameter: The parameter (its name, unit and meaning).
        lower: Lower bound [unit].
        upper: Upper bound [unit], > lower.
        start: Where the search starts [unit], within the bounds.
        loads: Whether any load depends on it (False for the end stops).
    """

    parameter: DesignParameter
    lower: float
    upper: float
    start: float
    loads: bool

    @property
    def name(self) -> str:
        """The parameter's name (``L1``, ``payload.mass``)."""
        return self.parameter.name

    @property
    def unit(self) -> str:
        """``m`` or ``kg``."""
        return self.parameter.unit


@dataclass(frozen=True)
class DesignSpace:
    """A design file, checked.

    Attributes:
        variables: The free parameters, in the file's order.
        device: The device with the ``[fixed]`` values set (the variables at their starts).
        band_deg: The transmission angle's band (low, high) [deg].
        toggle_margin_deg: Least distance of the transmission angle from 0° and 180° [deg].
        clearance: The travel's piston position stays this far inside the end stops [m].
        max_stroke: r2_max − r2_min at most [m].
        limits: Peak name → the largest magnitude allowed [its SI unit].
        text: The file's text (for the manifest's hash).
    """

    variables: tuple[Variable, ...]
    device: FeederParameters
    band_deg: tuple[float, float]
    toggle_margin_deg: float
    clearance: float
    max_stroke: float
    limits: dict[str, float]
    text: str


def _choices() -> dict[str, DesignParameter]:
    known = {parameter.name: parameter for parameter in design_parameters()}
    for name, meaning in END_STOPS.items():
        known[name] = DesignParameter(name, "m", meaning)
    return known


def _parameter(where: str, name: str, known: dict[str, DesignParameter]) -> DesignParameter:
    if name in known:
        return known[name]
    why = why_not(name, "free")
    near = difflib.get_close_matches(name, list(known), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else f"; choose from {', '.join(known)}"
    raise InputError(f"{where} names {name!r}, not a free parameter of the device: {why}{hint}")


def table_of(where: str, data: dict, key: str) -> dict:
    """The TOML table ``[key]`` of ``data`` (empty when absent); refused unless a table."""
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise InputError(f"{where}: [{key}] must be a table, got {value!r}")
    return value


def _variable(
    where: str, parameter: DesignParameter, entry: object, device: FeederParameters
) -> Variable:
    name = f"{where}: [variables] {parameter.name}"
    if not isinstance(entry, dict) or not {"lower", "upper"} <= set(entry):
        raise InputError(
            f"{name} must be {{lower = …, upper = …}} [{parameter.unit}], got {entry!r}"
        )
    if unknown := sorted(set(entry) - {"lower", "upper", "start"}):
        raise InputError(f"{name}: unknown key {unknown[0]!r}; use lower, upper and start")
    lower = check_number(f"{name} lower [{parameter.unit}]", entry["lower"])
    upper = check_number(f"{name} upper [{parameter.unit}]", entry["upper"])
    if not lower < upper:
        raise InputError(
            f"{name}: lower {lower:g} must be below upper {upper:g} {parameter.unit} "
            "(a parameter that does not vary belongs in [fixed])"
        )
    value = parameter.value(device)
    start = entry.get("start", min(max(value, lower), upper))
    start = check_number(f"{name} start [{parameter.unit}]", start)
    if not lower <= start <= upper:
        raise InputError(
            f"{name}: start {start:g} is outside [{lower:g}, {upper:g}] {parameter.unit}"
        )
    for bound, text in ((lower, "lower"), (upper, "upper")):
        try:
            parameter.changed(device, bound).check()
        except FeederError as exc:
            raise InputError(
                f"{name}: the {text} bound {bound:g} {parameter.unit}: {exc}"
            ) from exc
    return Variable(parameter, lower, upper, start, parameter.name not in END_STOPS)


def _constraints(where: str, table: dict) -> tuple[tuple[float, float], float, float, float]:
    if unknown := sorted(set(table) - set(CONSTRAINT_KEYS)):
        raise InputError(
            f"{where}: [constraints] has no key {unknown[0]!r}; keys: {CONSTRAINT_KEYS}"
        )
    built_in = tomllib.loads(BUILT_IN)["constraints"]
    values = built_in | table
    band = values["transmission_band_deg"]
    if not isinstance(band, list) or len(band) != 2:
        raise InputError(f"{where}: transmission_band_deg must be [low, high] [deg], got {band!r}")
    low, high = (check_number(f"{where}: transmission_band_deg [deg]", b) for b in band)
    if not 0.0 <= low < high <= 180.0:
        raise InputError(
            f"{where}: transmission_band_deg must satisfy 0 ≤ low < high ≤ 180 [deg], got {band!r}"
        )
    margin = check_number(f"{where}: toggle_margin_deg [deg]", values["toggle_margin_deg"])
    if not TOGGLE <= margin < 90.0:
        raise InputError(
            f"{where}: toggle_margin_deg must be in [{TOGGLE:g}, 90) [deg] (the pipeline "
            f"refuses poses within {TOGGLE:g}° of the toggle), got {margin!r}"
        )
    clearance = check_number(f"{where}: end_stop_clearance [m]", values["end_stop_clearance"])
    stroke = check_number(f"{where}: max_stroke [m]", values["max_stroke"])
    if clearance < 0.0 or stroke <= 2.0 * clearance:
        raise InputError(
            f"{where}: end_stop_clearance must be ≥ 0 and max_stroke above twice it [m], got "
            f"{clearance!r} and {stroke!r}"
        )
    return (low, high), margin, clearance, stroke


def _limits(where: str, table: dict) -> dict[str, float]:
    limits = {}
    for name, value in table.items():
        if name not in QUANTITIES:
            hint = did_you_mean(name, QUANTITIES)
            raise InputError(
                f"{where}: [limits] names {name!r}, no peak of the sweep; {hint}peaks: "
                f"{', '.join(QUANTITIES)}"
            )
        limits[name] = check_number(f"{where}: [limits] {name}", value)
        if limits[name] <= 0.0:
            raise InputError(f"{where}: [limits] {name} must be positive, got {value!r}")
    return limits


def design_space(text: str, device: FeederParameters, where: str = "the design") -> DesignSpace:
    """The design of the TOML ``text`` (module docstring) for ``device``, checked.

    Raises:
        InputError: Not TOML; an unknown table or key; a parameter that is not free (unknown,
            an angle, …); a variable both free and fixed; bounds not numbers, lower ≥ upper, a
            start outside them, a bound at which the device fails its checks (d3 ≤ 0, …); a
            band, margin, clearance or stroke out of range; a limit on no peak or ≤ 0.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where} is not a TOML design file: {exc}") from exc
    if unknown := sorted(set(data) - set(KEYS)):
        raise InputError(f"{where}: unknown table {unknown[0]!r}; a design has {', '.join(KEYS)}")
    known = _choices()
    fixed = table_of(where, data, "fixed")
    for name, value in fixed.items():
        parameter = _parameter(f"{where}: [fixed]", name, known)
        number = check_number(f"{where}: [fixed] {name} [{parameter.unit}]", value)
        device = parameter.changed(device, number)
    entries = table_of(where, data, "variables")
    if not entries:
        raise InputError(f"{where}: [variables] is empty: name at least one free parameter")
    variables = []
    for name, entry in entries.items():
        parameter = _parameter(f"{where}: [variables]", name, known)
        if name in fixed:
            raise InputError(f"{where}: {name} is both in [variables] and in [fixed]: keep one")
        variables.append(_variable(where, parameter, entry, device))
    if not any(variable.loads for variable in variables):
        raise InputError(f"{where}: every variable is an end stop: no load would change")
    for variable in variables:
        device = variable.parameter.changed(device, variable.start)
    band, margin, clearance, stroke = _constraints(where, table_of(where, data, "constraints"))
    limits = _limits(where, table_of(where, data, "limits"))
    return DesignSpace(tuple(variables), device, band, margin, clearance, stroke, limits, text)


def read_design(path: str | Path | None, device: FeederParameters) -> DesignSpace:
    """The design file ``path`` (None: :data:`BUILT_IN`) for ``device``, checked
    (:func:`design_space`)."""
    if path is None:
        return design_space(BUILT_IN, device, "the built-in design")
    return design_space(design_text(path), device, str(path))


def design_text(path: str | Path) -> str:
    """The text of the design file ``path`` (the device's or a mechanism's).

    Raises:
        InputError: It cannot be read, or is not text.
    """
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise InputError(f"cannot read the design file {path}: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise InputError(f"{path} is not a TOML design file: {exc}") from exc


def with_values(space: DesignSpace, values) -> FeederParameters:
    """The device with each variable set to ``values`` [its unit], (n,)."""
    device = space.device
    for variable, value in zip(space.variables, values, strict=True):
        device = variable.parameter.changed(device, float(value))
    return device
