"""Every joint kind's coordinates by name and unit: how a pose, a table's columns and a message
show them (numpy).

=================  ===========================================  ==================================
kind               shown coordinates                            velocity components
=================  ===========================================  ==================================
``revolute``       the angle [rad]                              its rate
``continuous``     the angle atan2(sin, cos) in (−π, π] [rad]   its rate
``prismatic``      the slide [m]                                its rate
``universal``      ``r1``, ``r2``: the turns about the first    ``r1``, ``r2``: their rates
                   axis and the turned second [rad]
``spherical_zyx``  ``rz``, ``ry``, ``rx``: the turns about z,   ``rz``, ``ry``, ``rx``: their rates
                   the turned y, the turned x [rad]
``translation``    ``x``, ``y``, ``z`` [m]                      ``vx``, ``vy``, ``vz``
``spherical``      ``rx``, ``ry``, ``rz``: the rotation vector  ``wx``, ``wy``, ``wz``: the angular
                   (axis × angle) [rad]; ``qx``, ``qy``, ``qz``,  velocity in the child's axes
                   ``qw``: the unit quaternion [–]
``planar``         ``x``, ``y`` [m]; ``theta`` [rad]             ``vx``, ``vy`` (child's axes),
                                                                ``wz``
``free_flyer``     ``x``, ``y``, ``z`` [m]; ``rx``, ``ry``,     ``vx``, ``vy``, ``vz``, ``wx``,
                   ``rz`` [rad]; ``qx``, ``qy``, ``qz``, ``qw``  ``wy``, ``wz`` (child's axes)
=================  ===========================================  ==================================

A one-coordinate joint's coordinate has no name of its own (the empty suffix): the joint's name
is enough. Rotations are shown as both a rotation vector (readable) and the quaternion (exact,
what a table is read back from).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .joints import kind_of


@dataclass(frozen=True)
class Coordinates:
    """How one kind of joint shows its configuration and names its velocity components.

    Attributes:
        shown: (suffix, unit) of each shown coordinate: ``m``, ``rad`` or ``–`` (a quaternion's
            component).
        rates: (suffix, unit of the coordinate it is the rate of) of each velocity component,
            in Pinocchio's velocity order.
        show: The shown coordinates (N, len(shown)) of the joint's q (N, nq_j).
        store: The joint's q (N, nq_j) from its shown coordinates (N, len(shown)).
    """

    shown: tuple[tuple[str, str], ...]
    rates: tuple[tuple[str, str], ...]
    show: Callable[[np.ndarray], np.ndarray]
    store: Callable[[np.ndarray], np.ndarray]


def _same(q: np.ndarray) -> np.ndarray:
    return q


def _angle(q: np.ndarray) -> np.ndarray:
    """(cos θ, sin θ) columns (N, 2) → θ (N, 1) in (−π, π]."""
    return np.arctan2(q[:, 1], q[:, 0])[:, None]


def _circle(theta: np.ndarray) -> np.ndarray:
    """θ (N, 1) → (cos θ, sin θ) (N, 2)."""
    return np.column_stack([np.cos(theta[:, 0]), np.sin(theta[:, 0])])


def _rotation(quaternion: np.ndarray) -> np.ndarray:
    """Unit quaternions (N, 4) (x, y, z, w) → rotation vectors (N, 3) and the quaternions."""
    vectors = [pin.log3(pin.Quaternion(x).matrix()) for x in quaternion]
    return np.column_stack([np.reshape(vectors, (-1, 3)), quaternion])


_XYZ = (("x", "m"), ("y", "m"), ("z", "m"))
_ROTATION = (("rx", "rad"), ("ry", "rad"), ("rz", "rad"))
_QUATERNION = (("qx", "–"), ("qy", "–"), ("qz", "–"), ("qw", "–"))
_LINEAR = (("vx", "m"), ("vy", "m"), ("vz", "m"))
_ANGULAR = (("wx", "rad"), ("wy", "rad"), ("wz", "rad"))
_ANGLES_ZYX = (("rz", "rad"), ("ry", "rad"), ("rx", "rad"))
_ANGLES_12 = (("r1", "rad"), ("r2", "rad"))

COORDINATES = {
    "revolute": Coordinates((("", "rad"),), (("", "rad"),), _same, _same),
    "continuous": Coordinates((("", "rad"),), (("", "rad"),), _angle, _circle),
    "prismatic": Coordinates((("", "m"),), (("", "m"),), _same, _same),
    "universal": Coordinates(_ANGLES_12, _ANGLES_12, _same, _same),
    "spherical_zyx": Coordinates(_ANGLES_ZYX, _ANGLES_ZYX, _same, _same),
    "translation": Coordinates(_XYZ, _LINEAR, _same, _same),
    "spherical": Coordinates(
        _ROTATION + _QUATERNION, _ANGULAR, _rotation, lambda shown: shown[:, 3:7]
    ),
    "planar": Coordinates(
        _XYZ[:2] + (("theta", "rad"),),
        _LINEAR[:2] + _ANGULAR[2:],
        lambda q: np.column_stack([q[:, :2], _angle(q[:, 2:4])]),
        lambda shown: np.column_stack([shown[:, :2], _circle(shown[:, 2:3])]),
    ),
    "free_flyer": Coordinates(
        _XYZ + _ROTATION + _QUATERNION,
        _LINEAR + _ANGULAR,
        lambda q: np.column_stack([q[:, :3], _rotation(q[:, 3:7])]),
        lambda shown: np.column_stack([shown[:, :3], shown[:, 6:10]]),
    ),
}
"""Every kind of :func:`~feeder.chain.kinematics.joints.kind_of` (the module docstring)."""


def coordinates(model: pin.Model, j: int) -> Coordinates:
    """The :class:`Coordinates` of joint ``j`` of ``model``.

    Raises:
        InputError: A joint type the kinematics do not handle (named).
    """
    return COORDINATES[kind_of(model.joints[j])]


def length_rates(model: pin.Model) -> np.ndarray:
    """Which velocity components (nv,) are lengths' rates [m/s] (prismatic joints, the linear
    parts of translation, planar and free-flyer joints); the others are angular [rad/s]."""
    lengths = np.zeros(model.nv, dtype=bool)
    for j in range(1, model.njoints):
        start = model.joints[j].idx_v
        for k, (_, unit) in enumerate(coordinates(model, j).rates):
            lengths[start + k] = unit == "m"
    return lengths


def pose_values(
    model: pin.Model, q: np.ndarray, joints: list[int] | None = None
) -> list[tuple[str, str, float, str]]:
    """A pose (nq,) as (joint, coordinate suffix, value, unit) rows, the shown coordinates of
    each joint of ``joints`` (ids; default every joint), in model order."""
    rows = []
    for j in range(1, model.njoints) if joints is None else sorted(joints):
        joint, table = model.joints[j], coordinates(model, j)
        shown = table.show(q[None, joint.idx_q : joint.idx_q + joint.nq])[0]
        for (suffix, unit), value in zip(table.shown, shown, strict=True):
            rows.append((model.names[j], suffix, float(value), unit))
    return rows


def pose_text(model: pin.Model, q: np.ndarray, joints: list[int] | None = None) -> str:
    """A pose (nq,) as one line of labelled values, ``crank = 0.7 rad, base x = 0.1 m, …``
    (:func:`pose_values`; 6 significant digits)."""
    return ", ".join(
        f"{name}{' ' + suffix if suffix else ''} = {value:.6g}{'' if unit == '–' else ' ' + unit}"
        for name, suffix, value, unit in pose_values(model, q, joints)
    )
