"""Physical consistency of a rigid body's mass and inertia (numpy only), and plausibility of a
model's bodies.

Pinocchio accepts a negative mass and a tensor no rigid body can have; every inertia that enters a
model is checked here first. What real CAD exports contain is accepted: frame links of zero mass
and zero inertia (attached by fixed joints, they only add frames to their parent's body), and the
idealised shapes whose principal moments meet the triangle inequality with equality — a lamina
(I₃ = I₁ + I₂) or a thin rod (one moment zero, two equal). Legal but implausible bodies get a
:class:`~feeder.exceptions.FeederWarning` naming them (:func:`check_bodies`).
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin

from ...exceptions import FeederWarning, InertiaError

ROUND_OFF = 1e-9
"""Relative slack [-] of the positivity and triangle tests, against the largest principal moment:
the eigenvalues of a tensor written with 6–20 significant digits (as exports print them) are
exact to ~1e-15 relative; a lamina or a rod written with 9 digits lands within 1e-9 of its
limiting case, while a tensor that breaks the triangle inequality by a physical amount (1 % of
its moments, say) is still refused."""

HEAVY = 100.0
"""A moving body more than this many times heavier than the median moving body gets a warning
(the 654-tonne ``sphere`` in a linkage of 25 kg bars is a CAD material slip)."""


def check_inertia(link: str, mass: float, inertia: np.ndarray) -> None:
    """Raise :class:`InertiaError` naming ``link`` unless ``mass`` and ``inertia`` are physical.

    Accepted: mass ≥ 0, a symmetric tensor with principal moments ≥ 0 that meet the triangle
    inequality I_k ≤ I_i + I_j, equality included (laminae, rods, and the zero tensor of a frame
    link), each within :data:`ROUND_OFF`.

    Args:
        link: Link name, for the message.
        mass: Mass [kg].
        inertia: (3, 3) rotational inertia about the centre of gravity [kg·m²].
    """
    values = np.append(np.ravel(inertia), mass)
    if not np.all(np.isfinite(values)):
        raise InertiaError(link, f"mass or inertia is not finite (mass={mass!r})")
    if mass < 0.0:
        raise InertiaError(link, f"mass must not be negative, got {mass!r} kg")
    inertia = np.asarray(inertia, dtype=float)
    size = float(np.abs(inertia).max())
    if not np.allclose(inertia, inertia.T, rtol=0.0, atol=1e-12 * max(1.0, size)):
        raise InertiaError(link, "inertia tensor is not symmetric")
    principal = np.linalg.eigvalsh(inertia)
    slack = ROUND_OFF * max(float(principal[-1]), 0.0)
    if principal[0] < -slack:
        raise InertiaError(
            link,
            f"inertia tensor is not positive semi-definite (principal moments {principal} "
            "kg·m²): a negative moment",
        )
    total = principal.sum()
    for moment in principal:
        if moment > total - moment + slack:
            raise InertiaError(
                link,
                f"principal moment {moment:.6g} kg·m² is larger than the sum of the other two "
                f"({total - moment:.6g} kg·m²): no rigid body has this inertia "
                "(triangle inequality)",
            )
    if mass == 0.0 and principal[-1] > 0.0:
        raise InertiaError(link, f"a body without mass cannot have moments of inertia {principal}")


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
    for j in range(1, model.njoints):
        body = model.inertias[j]
        name = model.names[j]
        if positive.size > 2 and body.mass > HEAVY * median:
            warnings.warn(
                f"{source}: the body of joint {name!r} weighs {body.mass:.6g} kg, "
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
                f"{source}: the body of joint {name!r} has a principal moment of {largest:.6g} "
                f"kg·m², more than a body of {body.mass:.6g} kg reaching {radius:.3g} m from its "
                f"centre of gravity can have ({body.mass * (2.0 * radius) ** 2:.3g} kg·m²): "
                "check its inertia (units?)",
                FeederWarning,
                stacklevel=3,
            )
