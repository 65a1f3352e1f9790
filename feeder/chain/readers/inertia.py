"""Physical consistency of a rigid body's mass and inertia (numpy only).

Pinocchio accepts a negative mass and a tensor no rigid body can have; every inertia that enters a
model is checked here first.
"""

from __future__ import annotations

import numpy as np

from ...exceptions import InertiaError


def check_inertia(link: str, mass: float, inertia: np.ndarray) -> None:
    """Raise :class:`InertiaError` naming ``link`` unless ``mass`` and ``inertia`` are physical.

    Args:
        link: Link name, for the message.
        mass: Mass [kg].
        inertia: (3, 3) rotational inertia about the centre of gravity [kg·m²].
    """
    values = np.append(np.ravel(inertia), mass)
    if not np.all(np.isfinite(values)):
        raise InertiaError(link, f"mass or inertia is not finite (mass={mass!r})")
    if mass <= 0.0:
        raise InertiaError(link, f"mass must be positive, got {mass!r} kg")
    inertia = np.asarray(inertia, dtype=float)
    if not np.allclose(inertia, inertia.T, rtol=0.0, atol=1e-12 * max(1.0, np.abs(inertia).max())):
        raise InertiaError(link, "inertia tensor is not symmetric")
    principal = np.linalg.eigvalsh(inertia)
    if principal[0] <= 0.0:
        raise InertiaError(
            link, f"inertia tensor is not positive definite (principal moments {principal})"
        )
    total = principal.sum()
    for moment in principal:
        if moment >= total - moment:
            raise InertiaError(
                link,
                f"principal moment {moment:.6g} kg·m² is not smaller than the sum of the other "
                f"two ({total - moment:.6g} kg·m²): no rigid body has this inertia "
                "(triangle inequality)",
            )
