"""MJCF models through Pinocchio's parser, their ``<equality>`` constraints as closures.

Pinocchio 4.1's MJCF reader misreads what it does not support instead of refusing it: it keeps
only the first body under ``<worldbody>`` (a constraint to the others then points at the world
with an uninitialised placement, and once crashed the process), ignores ``<include>`` and the
``<equality>`` types other than ``connect`` and ``weld``, and builds negative or NaN masses. So
every MJCF file is checked here first (:func:`check_mjcf`), strictly, and what the reader would
misread is refused with a :class:`~feeder.exceptions.UrdfError` naming the element; the built
model's bodies are checked again (:func:`~feeder.inertia.check_inertia`).
"""

from __future__ import annotations

import math
from pathlib import Path

import pinocchio as pin
from lxml import etree

from ...exceptions import UrdfError
from ...inertia import check_inertia
from ...validation import check_path
from ..model.closure import Closure
from .urdf import parse_xml_file

UNSUPPORTED = ("include", "replicate", "attach", "frame", "composite", "flexcomp")
"""MJCF elements Pinocchio's reader skips or misreads: refused."""

EQUALITIES = ("connect", "weld")
"""The ``<equality>`` types read (as point and weld closures)."""


def check_mjcf(path: Path) -> etree._Element:
    """Parse an MJCF file strictly and refuse what Pinocchio's reader would misread (module
    docstring): several bodies under ``<worldbody>``, the :data:`UNSUPPORTED` elements, equality
    types other than :data:`EQUALITIES`, masses, densities and inertias that are not finite and
    non-negative.

    Raises:
        InputError: ``path`` is not text or a path.
        UrdfError: Missing or malformed file, or one of the above, named.
    """
    path = check_path("the MJCF file", path)
    root = parse_xml_file(path, "MJCF", "mujoco")
    for element in root.iter(*UNSUPPORTED):
        raise UrdfError(
            f"{path}: <{element.tag}> (line {element.sourceline}) is not supported by the MJCF "
            "reader: write its content out in the file"
        )
    for world in root.iter("worldbody"):
        bodies = [body.get("name", "?") for body in world.findall("body")]
        if len(bodies) > 1:
            raise UrdfError(
                f"{path}: <worldbody> holds {len(bodies)} bodies ({', '.join(bodies)}): the "
                "reader "
                "keeps only the first; put them all under one body without a joint"
            )
    for equality in root.iter("equality"):
        for element in equality:
            if isinstance(element.tag, str) and element.tag not in EQUALITIES:
                raise UrdfError(
                    f"{path}: <equality><{element.tag}> (line {element.sourceline}) is not "
                    f"supported; the constraints read are {', '.join(EQUALITIES)}"
                )
    for element in root.iter("inertial", "geom", "default"):
        for attribute in ("mass", "density", "diaginertia", "fullinertia"):
            text = element.get(attribute)
            if text is None:
                continue
            try:
                values = [float(x) for x in text.split()]
            except ValueError:
                values = [math.nan]
            diagonal = values if attribute != "fullinertia" else values[:3]
            if not all(math.isfinite(x) for x in values) or any(x < 0.0 for x in diagonal):
                raise UrdfError(
                    f"{path}: <{element.tag} {attribute}={text!r}> (line {element.sourceline}) "
                    "must be finite and not negative"
                )
    return root


def read_mjcf(path: Path) -> tuple[pin.Model, list[Closure]]:
    """Pinocchio's MJCF model and its equality constraints as closures (frames added), after
    :func:`check_mjcf`.

    Raises:
        UrdfError: See :func:`check_mjcf`; also Pinocchio's own refusals.
        InertiaError: A built body whose mass or inertia is not physical.
    """
    root = check_mjcf(path)
    path = Path(path)
    try:
        model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    except (ValueError, RuntimeError) as exc:
        raise UrdfError(f"{path}: Pinocchio cannot read the MJCF model: {exc}") from exc
    for j in range(1, model.njoints):
        check_inertia(model.names[j], model.inertias[j].mass, model.inertias[j].inertia)
    equality = [
        element.get("name", "")
        for block in root.iter("equality")
        for element in block
        if element.tag in EQUALITIES
    ]
    closures = []
    for i, constraint in enumerate(constraints):
        names = (f"mjcf_constraint_{i}_a", f"mjcf_constraint_{i}_b")
        for name, joint, placement in zip(
            names,
            (constraint.joint1_id, constraint.joint2_id),
            (constraint.joint1_placement, constraint.joint2_placement),
            strict=True,
        ):
            parent_frame = model.getFrameId(model.names[joint]) if joint else 0
            model.addFrame(pin.Frame(name, joint, parent_frame, placement, pin.FrameType.OP_FRAME))
        kind = "weld" if constraint.type == pin.ContactType.CONTACT_6D else "point"
        label = (
            constraint.name or (equality[i] if i < len(equality) else "") or f"mjcf_constraint_{i}"
        )
        closures.append(Closure(*names, kind=kind, name=label))
    return model, closures
