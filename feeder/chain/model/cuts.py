"""The cut kinds: one class per joint that can be cut to open a loop, owning its rows.

A closure joins two frames, a and b, that coincide (or turn about a common axis) when the loop
is assembled. Each kind of cut is a :class:`Cut` subclass, registered in :data:`KINDS` under its
name, that owns everything about its rows: their number and labels, Pinocchio's constraints that
stand for it, and its rows' error, Jacobian, acceleration and reaction wrench. Each formula is
written once, on the two frames' world quantities (:class:`CutFrames`) at N samples: the batched
path (:mod:`feeder.chain.kinematics.rows`) feeds them from the tree's motion at every sample,
the per-sample path (:class:`~feeder.chain.model.closure.ClosedChain`) from Pinocchio's data,
one sample without the sample axis. The few products the formulas are made of (:func:`_cross`,
:func:`_turn`, :func:`_dot`, :func:`_log3`) take the cheapest numpy or Pinocchio call for one
sample, where numpy's cost per call outweighs the arithmetic.

=============  ====  ==============================================================================
kind           rows  the cut joint and its rows (world axes; "a minus b")
=============  ====  ==============================================================================
``point``      3     spherical pin: p_a − p_b
``weld``       6     rigid joint: p_a − p_b, and the relative rotation (its rows: ω_a − ω_b)
``revolute``   5     hinge about ``axis``: p_a − p_b, and the two components of frame b's hinge
                     axis u_b along n_1, n_2, the unit vectors of frame a that span the plane
                     perpendicular to its hinge (its rows: d_k · (ω_a − ω_b), d_k = n_k × u_b)
=============  ====  ==============================================================================

The constraint force conjugate to the rows acts on the body of frame a (and its opposite on the
body of frame b): a force [N] at frame a's origin for the point rows, a moment [N·m] for the
rotation rows. Pinocchio receives each cut as ``RigidConstraintModel`` s for
``constraintDynamics``: a ``CONTACT_3D`` for a point, a ``CONTACT_6D`` for a weld and, as
Pinocchio 4.1 has no hinge constraint, two ``CONTACT_3D`` on the hinge axis (:data:`HINGE_POINTS`
apart) for a revolute cut.

A new kind (a distance constraint, a prismatic cut) is one more subclass here with
:func:`register`: the closures, the readers' kind lists and every analysis pick it up. The
module is longer than the others (one concern, the cut kinds) so that every formula of a kind
sits in one place, as the issue that made it asked.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import pinocchio as pin

HINGE_POINTS = 0.1
"""Distance [m] along the hinge axis between the two point constraints that stand for a revolute
cut in Pinocchio's ``constraintDynamics``."""

NEAR_HALF_TURN = 1e-6
"""Below this sine of the angle, the rotation vector is not read off the antisymmetric part: near
0 the factor θ / (2 sin θ) is ½, near π that part vanishes and Pinocchio's log3 takes over."""


@dataclass(slots=True)
class CutFrames:
    """The two frames of one cut at N samples, world axes: what its rows are made of. The shapes
    below lose their leading N for one sample (the per-sample path).

    Attributes:
        rotation_a, rotation_b: World rotations R_a, R_b, (N, 3, 3).
        origin_a, origin_b: World origins p_a, p_b [m], (N, 3).
        jacobian_a, jacobian_b: World-aligned frame Jacobians [linear velocity of the origin;
            angular velocity] (N, 6, nv), or None where no Jacobian is asked for.
        omega_a, omega_b: Angular velocities [rad/s], (N, 3), or None (a position-level pass).
        alpha_a, alpha_b: Angular accelerations [rad/s²], (N, 3), or None.
        acceleration_a, acceleration_b: Classical accelerations of the origins [m/s²], (N, 3),
            or None.
        derived: What a cut computes from these frames for several of its results (a hinge's
            world axes), kept here once computed: a new evaluation builds new frames.
    """

    rotation_a: np.ndarray
    rotation_b: np.ndarray
    origin_a: np.ndarray
    origin_b: np.ndarray
    jacobian_a: np.ndarray | None = None
    jacobian_b: np.ndarray | None = None
    omega_a: np.ndarray | None = None
    omega_b: np.ndarray | None = None
    alpha_a: np.ndarray | None = None
    alpha_b: np.ndarray | None = None
    acceleration_a: np.ndarray | None = None
    acceleration_b: np.ndarray | None = None
    derived: dict[str, np.ndarray] = field(default_factory=dict)


class Cut:
    """One cut joint of a loop: its rows and everything computed from them.

    Subclasses set :attr:`kind` and :attr:`labels` and write the formulas; every method takes
    the two frames at N samples (:class:`CutFrames`) and returns arrays over them (without
    their leading N for one sample without it).

    Attributes:
        label: The closure's name in reports.
        axis, axis_b: The cut's axis in frame a's and in frame b's axes (unit vectors, (3,));
            only the kinds with an axis read them.
    """

    kind: ClassVar[str]
    """Its name in :data:`KINDS`, in closures and in side-files."""
    labels: ClassVar[tuple[str, ...]]
    """Names of its rows in reports (``ClosedChain.row_labels``)."""

    def __init__(self, label: str, axis: np.ndarray, axis_b: np.ndarray):
        self.label = label
        self.axis = np.array(axis, dtype=float)
        self.axis_b = np.array(axis_b, dtype=float)

    @property
    def rows(self) -> int:
        """Number of scalar constraints."""
        return len(self.labels)

    def constraint_models(
        self, model: pin.Model, frame_a: pin.Frame, frame_b: pin.Frame
    ) -> list[pin.RigidConstraintModel]:
        """Pinocchio's constraints standing for the cut (module docstring), LOCAL to frame a."""
        raise NotImplementedError

    def residual(self, frames: CutFrames) -> np.ndarray:
        """The rows' error [m, rad-like], (N, rows): zero where the loop is closed."""
        raise NotImplementedError

    def jacobian(self, frames: CutFrames) -> np.ndarray:
        """The rows' Jacobian (N, rows, nv): q̇ ↦ the rows' rates (module docstring). At a
        closed pose it spans the same rows as the residual's derivative."""
        raise NotImplementedError

    def residual_jacobian(self, frames: CutFrames) -> np.ndarray:
        """∂(residual)/∂q (N, rows, nv), the derivative Newton's method needs: the Jacobian,
        unless the kind's residual is not the integral of its rates away from closure."""
        return self.jacobian(frames)

    def acceleration(self, frames: CutFrames) -> np.ndarray:
        """The rows' second time derivative J q̈ + J̇ q̇ (N, rows) from the frames' velocities and
        accelerations (with q̈ = 0: the bias J̇ q̇)."""
        raise NotImplementedError

    def wrench(self, frames: CutFrames, forces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The force [N] and moment [N·m] about frame a's origin, world axes, each (N, 3), that
        the row forces ``forces`` (N, rows) exert on the body of frame a (the opposite acts on
        the body of frame b)."""
        raise NotImplementedError

    def alignment(self, frames: CutFrames) -> np.ndarray | None:
        """For a kind whose rows also vanish when the cut is assembled upside down: the cosine
        (N,) between its two axes (1 assembled, −1 upside down, which no real joint can be);
        None for the others."""
        return None

    def _constraint(
        self,
        model: pin.Model,
        frame_a: pin.Frame,
        frame_b: pin.Frame,
        contact: pin.ContactType,
        shift_a: pin.SE3 | None = None,
        shift_b: pin.SE3 | None = None,
        suffix: str = "",
    ) -> pin.RigidConstraintModel:
        """One Pinocchio constraint between the frames' bodies, at the frames (shifted by
        ``shift_a``, ``shift_b`` in their axes), LOCAL to frame a, named after the cut."""
        placement_a = frame_a.placement if shift_a is None else frame_a.placement * shift_a
        placement_b = frame_b.placement if shift_b is None else frame_b.placement * shift_b
        constraint = pin.RigidConstraintModel(
            contact,
            model,
            frame_a.parentJoint,
            placement_a,
            frame_b.parentJoint,
            placement_b,
            pin.LOCAL,
        )
        constraint.name = self.label + suffix
        return constraint


KINDS: dict[str, type[Cut]] = {}
"""The cut kinds by name: what closures, side-files and every reader accept."""


def register(cls: type[Cut]) -> type[Cut]:
    """Class decorator: add a :class:`Cut` subclass to :data:`KINDS` under its ``kind``."""
    KINDS[cls.kind] = cls
    return cls


@register
class PointCut(Cut):
    """A spherical pin: frame a's origin on frame b's, p_a − p_b (3 rows)."""

    kind = "point"
    labels = ("fx", "fy", "fz")

    def constraint_models(self, model, frame_a, frame_b):
        return [self._constraint(model, frame_a, frame_b, pin.ContactType.CONTACT_3D)]

    def residual(self, frames):
        return frames.origin_a - frames.origin_b

    def jacobian(self, frames):
        return frames.jacobian_a[..., :3, :] - frames.jacobian_b[..., :3, :]

    def acceleration(self, frames):
        return frames.acceleration_a - frames.acceleration_b

    def wrench(self, frames, forces):
        force = forces[..., :3]
        return force, np.zeros_like(force)


@register
class WeldCut(PointCut):
    """A rigid joint: the point rows, and the relative rotation log3(R_a R_bᵀ) [rad] whose rates
    are ω_a − ω_b (6 rows)."""

    kind = "weld"
    labels = ("fx", "fy", "fz", "mx", "my", "mz")

    def constraint_models(self, model, frame_a, frame_b):
        return [self._constraint(model, frame_a, frame_b, pin.ContactType.CONTACT_6D)]

    def residual(self, frames):
        relative = frames.rotation_a @ np.swapaxes(frames.rotation_b, -1, -2)
        return np.concatenate([super().residual(frames), _log3(relative)], axis=-1)

    def jacobian(self, frames):
        return frames.jacobian_a - frames.jacobian_b

    def residual_jacobian(self, frames):
        """The rotation rows' exact derivative: d log3(R)/dt = Jlog3(R) (Rᵀ ω_a − ω_b) with
        R = R_a R_bᵀ, which is ω_a − ω_b only where R = I."""
        relative = frames.rotation_a @ np.swapaxes(frames.rotation_b, -1, -2)
        turning = (
            np.swapaxes(relative, -1, -2) @ frames.jacobian_a[..., 3:, :]
            - frames.jacobian_b[..., 3:, :]
        )
        return np.concatenate([super().jacobian(frames), _jlog3(relative) @ turning], axis=-2)

    def acceleration(self, frames):
        spin = frames.alpha_a - frames.alpha_b
        return np.concatenate([super().acceleration(frames), spin], axis=-1)

    def wrench(self, frames, forces):
        return forces[..., :3], forces[..., 3:6]


@register
class RevoluteCut(PointCut):
    """A hinge about ``axis`` (frame a) and ``axis_b`` (frame b): the point rows, and the two
    components n_k · u_b of frame b's hinge axis u_b along the unit vectors n_1, n_2 of frame a
    perpendicular to its hinge (5 rows).

    Attributes:
        normals: n_1, n_2 in frame a's axes, (2, 3), with (n_1, n_2, axis) right-handed.
    """

    kind = "revolute"
    labels = ("fx", "fy", "fz", "m1", "m2")
    """m1, m2: the moments about d_1 = n_1 × u, d_2 = n_2 × u perpendicular to the hinge u
    (d_1 = −n_2, d_2 = n_1 at an assembled hinge)."""

    def __init__(self, label, axis, axis_b):
        super().__init__(label, axis, axis_b)
        helper = np.eye(3)[int(np.argmin(np.abs(self.axis)))]
        first = np.cross(helper, self.axis)
        first /= np.linalg.norm(first)
        self.normals = np.array([first, np.cross(self.axis, first)])

    def constraint_models(self, model, frame_a, frame_b):
        shift_a = pin.SE3(np.eye(3), HINGE_POINTS * self.axis)
        shift_b = pin.SE3(np.eye(3), HINGE_POINTS * self.axis_b)
        contact = pin.ContactType.CONTACT_3D
        return [
            self._constraint(model, frame_a, frame_b, contact, suffix=":origin"),
            self._constraint(model, frame_a, frame_b, contact, shift_a, shift_b, ":axis"),
        ]

    def _hinge(self, frames: CutFrames) -> tuple[np.ndarray, np.ndarray]:
        """n_1, n_2 in world axes (N, 2, 3) and u_b (N, 3)."""
        derived = frames.derived
        if "normals" not in derived:
            derived["normals"] = np.swapaxes(_turn(frames.rotation_a, self.normals.T), -1, -2)
            derived["u_b"] = _turn(frames.rotation_b, self.axis_b)
        return derived["normals"], derived["u_b"]

    def directions(self, frames: CutFrames) -> np.ndarray:
        """The hinge rows' directions d_k = n_k × u_b, world axes, (N, 2, 3)."""
        if "directions" not in frames.derived:
            normals, u_b = self._hinge(frames)
            frames.derived["directions"] = _cross(normals, u_b[..., None, :])
        return frames.derived["directions"]

    def residual(self, frames):
        normals, u_b = self._hinge(frames)
        return np.concatenate([super().residual(frames), _dot(normals, u_b)], axis=-1)

    def jacobian(self, frames):
        spin = frames.jacobian_a[..., 3:, :] - frames.jacobian_b[..., 3:, :]
        hinge = self.directions(frames) @ spin
        return np.concatenate([super().jacobian(frames), hinge], axis=-2)

    def acceleration(self, frames):
        """The hinge rows: d/dt (d_k · (ω_a − ω_b)) with ṅ_k = ω_a × n_k, u̇_b = ω_b × u_b."""
        normals, u_b = self._hinge(frames)
        w_a, w_b = frames.omega_a, frames.omega_b
        rates = _cross(_cross(w_a[..., None, :], normals), u_b[..., None, :]) + _cross(
            normals, _cross(w_b, u_b)[..., None, :]
        )
        hinge = _dot(rates, w_a - w_b) + _dot(
            self.directions(frames), frames.alpha_a - frames.alpha_b
        )
        return np.concatenate([super().acceleration(frames), hinge], axis=-1)

    def wrench(self, frames, forces):
        moment = np.einsum("...k,...ki->...i", forces[..., 3:5], self.directions(frames))
        return forces[..., :3], moment

    def alignment(self, frames):
        u_a, u_b = _turn(frames.rotation_a, self.axis), self._hinge(frames)[1]
        return np.einsum("...i,...i->...", u_a, u_b)


def _cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Cross products u × w along the last axis, broadcast. Where one side is a single vector
    (one sample) it is a product with its skew matrix, n × w = n [w]×: one call instead of the
    six products (numpy's cost per call dominates on a few vectors; its ``cross`` is several
    times slower still)."""
    if w.size == 3:
        return u @ pin.skew(w.reshape(3))
    if u.size == 3:
        return w @ pin.skew(u.reshape(3)).T
    out = np.empty(np.broadcast_shapes(u.shape, w.shape))
    out[..., 0] = u[..., 1] * w[..., 2] - u[..., 2] * w[..., 1]
    out[..., 1] = u[..., 2] * w[..., 0] - u[..., 0] * w[..., 2]
    out[..., 2] = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
    return out


def _turn(rotations: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """Each rotation (..., 3, 3) times one vector (3,) or matrix (3, k): (..., 3) or
    (..., 3, k); N rotations as one (3N × 3) product (a stack of small products costs several
    times more)."""
    if rotations.ndim == 2:
        return rotations @ fixed
    product = rotations.reshape(-1, 3) @ fixed
    return product.reshape(*rotations.shape[:-1], *fixed.shape[1:])


def _dot(rows: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each sample's rows (..., k, 3) dotted with its vector (..., 3): (..., k)."""
    if vectors.ndim == 1:
        return rows @ vectors
    return np.einsum("...ki,...i->...k", rows, vectors)


def _log3(rotation: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) of rotation matrices (..., 3, 3), angles in [0, π]: Pinocchio's
    log3 for one matrix (the per-sample path), the same formula in numpy for N."""
    if rotation.ndim == 2:
        return pin.log3(rotation)
    cosine = np.clip((np.trace(rotation, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cosine)
    skew = np.stack(
        [
            rotation[:, 2, 1] - rotation[:, 1, 2],
            rotation[:, 0, 2] - rotation[:, 2, 0],
            rotation[:, 1, 0] - rotation[:, 0, 1],
        ],
        axis=1,
    )
    sine = np.sin(angle)
    near = sine <= NEAR_HALF_TURN
    factor = np.where(near, 0.5, angle / np.where(near, 1.0, 2.0 * sine))
    out = factor[:, None] * skew
    for k in np.flatnonzero(near & (cosine < 0.0)):  # near a half turn: the skew part vanishes
        out[k] = pin.log3(rotation[k])
    return out


def _jlog3(rotation: np.ndarray) -> np.ndarray:
    """Jacobians (..., 3, 3) of log3 at rotation matrices (..., 3, 3) (Pinocchio's Jlog3)."""
    if rotation.ndim == 2:
        return pin.Jlog3(rotation)
    return np.array([pin.Jlog3(r) for r in rotation]).reshape(rotation.shape)
