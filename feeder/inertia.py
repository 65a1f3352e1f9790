"""Physical consistency of a rigid body's mass and inertia (numpy only).

Pinocchio accepts a negative mass and a tensor no rigid body can have; every inertia that enters a
model is checked here first. What real CAD exports contain is accepted: frame links of zero mass
and zero inertia (attached by fixed joints, they only add frames to their parent's body), and the
idealised shapes whose principal moments meet the triangle inequality with equality — a lamina
(I₃ = I₁ + I₂) or a thin rod (one moment zero, two equal). Legal but implausible bodies get a
:class:`~feeder.exceptions.FeederWarning` naming them
(:mod:`feeder.chain.readers.bodies`).
"""

from __future__ import annotations

import numpy as np

from .exceptions import InertiaError, InputError

ROUND_OFF = 1e-9
"""Relative slack [-] of the positivity and triangle tests, against the largest principal moment:
the eigenvalues of a tensor written with 6–20 significant digits (as exports print them) are
exact to ~1e-15 relative; a lamina or a rod written with 9 digits lands within 1e-9 of its
limiting case, while a tensor that breaks the triangle inequality by a physical amount (1 % of
its moments, say) is still refused."""


def check_inertia(link: str, mass: float, inertia: np.ndarray) -> None:
    """Raise :class:`InertiaError` naming ``link`` unless ``mass`` and ``inertia`` are physical.

    Accepted: mass ≥ 0, a symmetric tensor with principal moments ≥ 0 that meet the triangle
    inequality I_k ≤ I_i + I_j, equality included (laminae, rods, and the zero tensor of a frame
    link), each within :data:`ROUND_OFF`.

    Args:
        link: Link name, for the message.
        mass: Mass [kg].
        inertia: (3, 3) rotational inertia about the centre of gravity [kg·m²].

    Raises:
        InputError: ``mass`` or ``inertia`` not numbers, or ``inertia`` not (3, 3).
    """
    try:
        tensor = np.asarray(inertia, dtype=float)
        number = None if isinstance(mass, str | bytes) else float(mass)
    except (TypeError, ValueError):
        tensor, number = np.zeros(0), None
    if number is None or tensor.shape != (3, 3):
        raise InputError(
            f"link '{link}': give the mass as a number [kg] and the inertia as a (3, 3) tensor "
            f"[kg·m²], got {mass!r} and {type(inertia).__name__} of shape {np.shape(inertia)}"
        )
    mass, inertia = number, tensor
    values = np.append(np.ravel(inertia), mass)
    if not np.all(np.isfinite(values)):
        raise InertiaError(link, f"mass or inertia is not finite (mass={mass!r})")
    if mass < 0.0:
        raise InertiaError(link, f"mass must not be negative, got {mass!r} kg")
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
