"""Exceptions raised by feeder.

Every error a user can provoke with bad input is a subclass of :class:`FeederError`, carries the
offending value in its message, and is raised before any library sees the input.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np


class FeederError(Exception):
    """Base class of every exception raised by feeder."""


class InputError(FeederError, ValueError):
    """A numeric input is out of its range, not finite, or of the wrong shape."""


class ElevationError(InputError):
    """An elevation outside the device's range [−4°, 70°]."""


class UrdfError(FeederError):
    """A URDF file is missing, malformed, or lacks what the model needs."""


class ClosureFrameError(UrdfError):
    """A frame named in a loop closure does not exist in the model."""


class InertiaError(FeederError, ValueError):
    """A link's mass or inertia tensor is not physical.

    Attributes:
        link: Name of the offending link.
    """

    def __init__(self, link: str, reason: str):
        super().__init__(f"link '{link}': {reason}")
        self.link = link


class UnreachablePoseError(FeederError):
    """The closed loop cannot be assembled at the requested independent coordinates."""


class SingularPoseError(FeederError):
    """The pose is at or too near a singularity (toggle) for a meaningful answer."""


class ForwardDivergenceError(FeederError):
    """The forward run left the joints' end stops or blew up: the integration has diverged.

    The force-driven mechanism is unstable (a deviation grows like e^(4…6 t)), so a coarse step
    or a long cycle lets the integration error grow until the motion is no longer the one the
    loads were computed for.
    """


class ViewerPortError(FeederError):
    """The viewer's web port on 127.0.0.1 cannot be used (busy, or not permitted)."""


def check_finite(name: str, value: float | Iterable[float] | np.ndarray) -> np.ndarray:
    """Return ``value`` as a float array, or raise :class:`InputError` if any entry is NaN/inf.

    Args:
        name: What the value is, for the message.
        value: Scalar or array-like.
    """
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric, got {value!r}") from exc
    if not np.all(np.isfinite(array)):
        bad = array.flat[int(np.argmin(np.isfinite(array).ravel()))]
        raise InputError(f"{name} must be finite, got {bad!r}")
    return array


def check_elevation(elevation: float, limits: tuple[float, float]) -> float:
    """Return the elevation [rad] if finite and inside ``limits`` [rad], else raise.

    Raises:
        InputError: NaN, infinite or non-scalar elevation.
        ElevationError: Elevation outside the range.
    """
    array = check_finite("elevation", elevation)
    if array.shape != ():
        raise InputError(f"elevation must be one number [rad], got {elevation!r}")
    eps = float(array)
    low, high = limits
    if not low - 1e-12 <= eps <= high + 1e-12:
        raise ElevationError(
            f"elevation {math.degrees(eps):.3f}° is outside the device's range "
            f"[{math.degrees(low):.1f}°, {math.degrees(high):.1f}°]"
        )
    return eps
