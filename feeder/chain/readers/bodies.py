"""Plausibility of a model's moving bodies: legal but implausible ones get a warning that names
them (a CAD material or unit slip)."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin

from ...exceptions import FeederWarning

HEAVY = 100.0
"""A moving body more than this many times heavier than the median moving body gets a warning
(the 654-tonne ``sphere`` in a linkage of 25 kg bars is a CAD material slip)."""


def check_bodies(model: pin.Model, source: str) -> None:
    """Warn (:class:`~feeder.exceptions.FeederWarning`) about each moving body of ``model`` that is
    implausible: far heavier than the rest (:data:`HEAVY`), or with a principal moment larger
    than any body of its size can have — m (2ρ)², ρ the largest distance from its centre of
    gravity to its joint, its children's joints and its frames (a box of edge 4ρ about the centre
    of gravity could not have more; a body attached at one point only is not sized). A body's
    inertia is Pinocchio's composite one: the links
    attached to it by fixed joints are part of it."""
    masses = np.array([model.inertias[j].mass for j in range(1, model.njoints)])
    positive = masses[masses > 0.0]
    median = float(np.median(positive)) if positive.size else 0.0
    reach: dict[int, list[np.ndarray]] = {j: [np.zeros(3)] for j in range(1, model.njoints)}
    for j in range(1, model.njoints):
        parent = model.parents[j]
        if parent > 0:
            reach[parent].append(model.jointPlacements[j].translation)
    for frame in model.frames:
        if frame.parentJoint > 0:
            reach[frame.parentJoint].append(frame.placement.translation)
    links: dict[int, list[str]] = {j: [] for j in range(model.njoints)}
    for frame in model.frames:
        if frame.type == pin.FrameType.BODY:
            links[frame.parentJoint].append(frame.name)
    for j in range(1, model.njoints):
        body = model.inertias[j]
        name = f"{model.names[j]}' (links {', '.join(links[j])})"
        if positive.size > 2 and body.mass > HEAVY * median:
            warnings.warn(
                f"{source}: the body of joint '{name} weighs {body.mass:.6g} kg, "
                f"{body.mass / median:.3g} times the median body ({median:.3g} kg): check its "
                "mass (a CAD material or unit slip?)",
                FeederWarning,
                stacklevel=3,
            )
        points = np.array(reach[j])
        if np.ptp(points, axis=0).max() == 0.0:
            continue  # one attachment point: the body's size is not known without its shape
        radius = float(np.linalg.norm(points - body.lever, axis=1).max())
        largest = float(np.linalg.eigvalsh(body.inertia)[-1])
        if body.mass > 0.0 and largest > body.mass * (2.0 * radius) ** 2:
            warnings.warn(
                f"{source}: the body of joint '{name} has a principal moment of {largest:.6g} "
                f"kg·m², more than a body of {body.mass:.6g} kg reaching {radius:.3g} m from its "
                f"centre of gravity can have ({body.mass * (2.0 * radius) ** 2:.3g} kg·m²): "
                "check its inertia (units?)",
                FeederWarning,
                stacklevel=3,
            )
