"""Force elements pushed by a controller (a ``[[control]]`` table's ``element``,
:mod:`~feeder.chain.dynamics.control`): the checks of a spec that drives a joint by a spring's or
a cylinder's push, a cylinder's chamber pressures for a push, and the chain's dynamics whose
pushed elements carry the pushes applied at a run's samples (for its loads)."""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Mapping

import numpy as np

from ...exceptions import InputError
from ...validation import did_you_mean
from ..model.control import ControlSpec
from ..model.forces import Cylinder, Spring, Table
from .elements import BoundElements, LineElement
from .inverse import ChainDynamics


def pushed_joint(dyn: ChainDynamics, spec: ControlSpec) -> int:
    """The velocity column of the joint a spec's element drives, checked: a joint of one
    coordinate, not actuated."""
    try:
        (column,) = dyn.chain.coordinate_columns([spec.joint], "controlled")
    except InputError as exc:
        raise InputError(f"{spec.where}: {exc}") from None
    if spec.joint in dyn.actuated:
        raise InputError(
            f"{spec.where}: joint {spec.joint!r} is actuated and element {spec.element!r} would "
            "push it too: drop element to drive the joint itself, or leave the joint out of "
            "the actuated joints to drive it by the element's push"
        )
    if spec.area is not None:
        raise InputError(
            f"{spec.where}: area is for a joint's own drive; the push of element "
            f"{spec.element!r} is in N (a Cylinder's pressures follow from its bore and rod)"
        )
    return int(column)


def pushed_element(dyn: ChainDynamics, spec: ControlSpec, taken: list) -> LineElement:
    """The bound spring or cylinder a spec's element names, checked: one of the chain's, with
    no push law of its own, not pushed for another joint (``taken``)."""
    elements = {element.name: element for element in dyn.elements.elements}
    element = elements.get(spec.element)
    if element is None:
        raise InputError(
            f"{spec.where}: no force element {spec.element!r}; "
            f"{did_you_mean(spec.element, elements)}the elements are {list(elements)}"
        )
    if not isinstance(element, Spring | Cylinder):
        raise InputError(
            f"{spec.where}: element {spec.element!r} is a {type(element).__name__}; a controlled "
            "element is a Spring or a Cylinder (a line whose push drives the joint)"
        )
    spring = isinstance(element, Spring)
    laws = (element.force,) if spring else (element.pressure, element.rod_pressure)
    if any(callable(law) or law != 0.0 for law in laws):
        what = "force" if spring else "pressure, rod_pressure"
        raise InputError(
            f"{spec.where}: element {spec.element!r} has a push law of its own ({what}); under "
            "control its push is the controller's: leave it at 0"
        )
    if any(line.name == element.name for line in taken):
        raise InputError(f"{spec.where}: element {spec.element!r} is pushed for two joints")
    return dyn.elements.line(element.name)


def chambers(cylinder: Cylinder, push: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cap and rod chambers' gauge pressures [Pa] (N,) each that give a cylinder's pushes
    (N,) [N]: p_cap = P/A_cap where P ≥ 0, p_rod = −P/A_ann where P < 0, the other 0."""
    cap = np.maximum(push, 0.0) / cylinder.cap_area
    return cap, np.maximum(-push, 0.0) / cylinder.annulus_area


def _with_pushes(element: Spring | Cylinder, t: np.ndarray, push: np.ndarray) -> Spring | Cylinder:
    """A copy of a pushed element whose push is the :class:`~feeder.chain.model.forces.Table`
    of the pushes [N] (N,) at the times t [s] (N,): a cylinder's as its chamber pressures."""
    source = f"the pushes the controller applied to {element.name!r}"
    if isinstance(element, Spring):
        return dataclasses.replace(element, force=Table(t, push, source))
    cap, rod = chambers(element, push)
    return dataclasses.replace(
        element, pressure=Table(t, cap, source), rod_pressure=Table(t, rod, source)
    )


def carrying(dyn: ChainDynamics, t: np.ndarray, pushes: Mapping[str, np.ndarray]) -> ChainDynamics:
    """A copy of ``dyn`` whose elements named in ``pushes`` carry those pushes [N] (N,) at the
    times t [s] (N,) as a :class:`~feeder.chain.model.forces.Table` (a cylinder's as its chamber
    pressures, :func:`chambers`): evaluated at those times, exactly the pushes (a table at its
    knots; a cylinder's to round-off)."""
    elements = [
        _with_pushes(element, t, pushes[element.name]) if element.name in pushes else element
        for element in dyn.elements.elements
    ]
    out = copy.copy(dyn)
    out.elements = BoundElements(dyn.chain, elements)
    return out
