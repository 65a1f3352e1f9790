"""MJCF models through Pinocchio's parser, their ``<equality>`` constraints as closures."""

from __future__ import annotations

from pathlib import Path

import pinocchio as pin

from ...exceptions import UrdfError
from ..model.closure import Closure
from .inertia import check_inertia


def read_mjcf(path: Path) -> tuple[pin.Model, list[Closure]]:
    """Pinocchio's MJCF model and its equality constraints as closures (frames added)."""
    if not path.is_file():
        raise UrdfError(f"MJCF file not found: {path}")
    try:
        model, constraints = pin.buildModelAndLegacyConstraintsFromMJCF(str(path))
    except (ValueError, RuntimeError) as exc:
        raise UrdfError(f"{path}: Pinocchio cannot read the MJCF model: {exc}") from exc
    for j in range(1, model.njoints):
        inertia = model.inertias[j]
        if inertia.mass > 0.0:
            check_inertia(model.names[j], inertia.mass, inertia.inertia)
    equality = _equality_names(path)
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


def _equality_names(path: Path) -> list[str]:
    """Names of an MJCF's ``equality/connect|weld`` elements, in file order ("" if unnamed):
    Pinocchio 4.1 leaves its constraint models unnamed."""
    from lxml import etree

    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    try:
        root = etree.parse(str(path), parser).getroot()
    except (OSError, etree.XMLSyntaxError) as exc:
        raise UrdfError(f"{path}: malformed MJCF: {exc}") from exc
    return [
        element.get("name", "")
        for equality in root.iter("equality")
        for element in equality
        if element.tag in ("connect", "weld")
    ]
