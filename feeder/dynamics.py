"""Inverse dynamics of the feeder's closed chain: the actuator loads and the pin force.

The open tree (:mod:`feeder.urdf`) cut at the rod-eye pin moves as the closed chain when the
pin force λ acts on the piston at ``piston_pin`` and −λ on the arm at ``arm_pin``:

    M(q) q̈ + b(q, q̇) = Sᵀ τ_act + Jᵀ λ                                          (cf. eq. 46)

* M q̈ + b (inertia, Coriolis and gravity, −y) is Pinocchio's RNEA of the open tree;
* J = ∂(p_piston_pin − p_arm_pin)/∂q is the closure's world-frame Jacobian (3 × 4), from
  Pinocchio's frame Jacobians, so Jᵀ λ is the generalized force of the pin force pair;
* S selects the actuated coordinates: the piston force on r2 (``piston_joint``) and the forearm
  moment on φ4 (``forearm_joint``); φ1 and φ3 are passive (zero generalized force).

Four equations, five unknowns (τ_piston, τ_forearm, λx, λy, λz), rank four. The loop is planar:
the cylinder and arm pivots turn about world z and the piston slides in the x–y plane, so the
z row of J vanishes identically (checked at every sample) and λz drops out of the equations. The
out-of-plane pin force is **statically indeterminate** in the rigid model: any pair ±λz along
the pin axis is balanced by bending moments in the cylinder's and the arm's pivots, which carry
moments about x and y. In the machine it is shared by the rod-eye bearing, the cylinder trunnions
and the arm bearing according to their axial stiffness, play and misalignment; rigid-body
mechanics cannot tell. We report the minimum-norm answer λz = 0: the arm–frame joint then carries
the whole out-of-plane load of the arm, forearm and payload (stages 1–2 swing the forearm in the
horizontal plane), and the piston and cylinder carry none of it. The remaining 3 × 3 system in
(τ_piston, λx, λy) is singular at the toggle (transmission angle 0° or 180°), which is refused
(:data:`~feeder.kinematics.SINGULAR_TRANSMISSION_DEG`).

The payload is gripped at the end of stage 1: samples with ``payload == 0`` use a copy of the
model whose forearm body lacks the payload's spatial inertia (:func:`payload_inertia`), so the
loads step at the grip. No URDF is regenerated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .device import CLOSURE, PAPER_JOINTS, Feeder
from .exceptions import InputError, UnreachablePoseError, check_finite
from .kinematics import check_transmission, pin_position

PAYLOAD_FRAME = "projectile"
"""Frame of the payload link (its centre of gravity, y = payload axis), fixed to the forearm."""

CLOSURE_TOLERANCE = 1e-9
"""Largest accepted closure error [m] of a given configuration (eq. 44): the closed form and the
Newton assembly close the loop to ~1e-15 m; 1e-9 m leaves room for data rounded to 9 digits."""

VELOCITY_TOLERANCE = 1e-9
"""Largest accepted closure velocity error |J q̇| [m/s] (same reasoning as the position)."""

PLANAR_TOLERANCE = 1e-12
"""Largest accepted |∂(pin gap)_z/∂q| [m]: exactly zero for a planar loop (rotations about z)."""

PROXIMAL_MU = 1e-8
"""Proximal regularisation of ``constraintDynamics`` [1/kg, the Delassus matrix's unit]. It must
be positive: the planar loop's out-of-plane row makes the Delassus matrix J M⁻¹ Jᵀ singular, and
mu = 0 gives NaN. Its in-plane eigenvalues are 0.48–0.64 1/kg along the cycle (the light piston
dominates), so each proximal iteration shrinks the in-plane force error by ~2e-8: 3 iterations
reach the accuracy below."""

PROXIMAL_ACCURACY = 1e-12
"""Stopping accuracy of the proximal iterations (relative)."""

PROXIMAL_MAX_ITERATIONS = 20
"""Iteration cap of the proximal solver (3 are used in practice)."""

BAUMGARTE_RATE = 20.0
"""Baumgarte corrector of the pin constraint in ``constraintDynamics`` [rad/s]: critically
damped, Kp = ω², Kd = 2ω (see :mod:`feeder.simulation` for the choice)."""


def payload_inertia(feeder: Feeder) -> pin.Inertia:
    """Spatial inertia of the payload in the forearm joint frame (mass [kg], CG [m], [kg·m²]).

    Built from the parameters (mass and central moments in the payload link frame) and the
    payload frame's placement in the forearm joint frame; Pinocchio merged the same body into
    the forearm joint's inertia when it read the URDF.
    """
    model = feeder.model
    frame = model.frames[feeder.frame_id(PAYLOAD_FRAME)]
    link = feeder.params.payload
    central = pin.Inertia(link.mass, np.zeros(3), np.diag(link.moments))
    return frame.placement.act(central)


def loop_residual(feeder: Feeder, q: np.ndarray) -> np.ndarray:
    """Closure error of eq. (44): pin from the cylinder side minus pin from the arm side [m].

    Args:
        q: Configurations in paper order, shape (N, 4).

    Returns:
        Shape (N,), the distance between the two pin positions in the x–y plane.
    """
    p = feeder.params
    reach = q[:, 1] + p.d2
    piston_side = np.array([reach * np.cos(q[:, 0]), reach * np.sin(q[:, 0])])
    return np.linalg.norm(piston_side - pin_position(p, q[:, 2]), axis=0)


def payload_runs(payload: np.ndarray) -> list[tuple[int, int, int]]:
    """Maximal runs of constant payload flag: [(start, stop, flag)], stop exclusive."""
    payload = np.asarray(payload, dtype=int)
    edges = np.flatnonzero(np.diff(payload)) + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges, [payload.size]])
    return [(int(a), int(b), int(payload[a])) for a, b in zip(starts, stops, strict=True)]


class InertiaCase:
    """One Pinocchio model of the device (with or without payload) and its reusable containers.

    Attributes:
        model: The open tree, gravity −y.
        data: Its data.
        constraint_models: The pin closure (``CONTACT_3D``, LOCAL frame of ``piston_pin``), a
            copy of the device's with the Baumgarte corrector set.
        constraint_datas: Their data, initialised for ``constraintDynamics``.
        prox: Proximal settings of ``constraintDynamics``.
        pool: Model pool for ``rneaInParallel`` (one thread).
    """

    def __init__(self, model: pin.Model, constraint_models: pin.StdVec_RigidConstraintModel):
        self.model = model
        self.data = model.createData()
        self.constraint_models = pin.StdVec_RigidConstraintModel()
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for constraint in constraint_models:
            own = pin.RigidConstraintModel(constraint)
            gains = own.m_baumgarte_parameters
            gains.Kp = BAUMGARTE_RATE**2
            gains.Kd = 2.0 * BAUMGARTE_RATE
            self.constraint_models.append(own)
            self.constraint_datas.append(own.createData())
        pin.initConstraintDynamics(
            self.model, self.data, self.constraint_models, self.constraint_datas
        )
        self.prox = pin.ProximalSettings(
            PROXIMAL_ACCURACY, PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_MAX_ITERATIONS
        )
        self.pool = pin.ModelPool(model, 1)


class FeederDynamics:
    """Everything the dynamics of one device needs that does not change along a cycle.

    Attributes:
        feeder: The device.
        payload: Payload spatial inertia in the forearm joint frame (:func:`payload_inertia`).
        cases: (without payload, with payload): index it with the ``payload`` flag.
        joint_ids: Pinocchio ids of ``cylinder_joint``, ``piston_joint``, ``arm_joint``,
            ``forearm_joint`` (paper order).
        index: Positions of [φ1, r2, φ3, φ4] in Pinocchio's v (``feeder.index``).
        closure_frames: Ids of the ``piston_pin`` and ``arm_pin`` frames.
        motion_subspaces: Joint id → its motion subspace S (6,) [linear, angular] in the joint
            frame (all joints have one degree of freedom).
    """

    def __init__(self, feeder: Feeder):
        self.feeder = feeder
        loaded = feeder.model
        self.joint_ids = tuple(loaded.getJointId(name) for name in PAPER_JOINTS)
        forearm = self.joint_ids[3]
        self.payload = payload_inertia(feeder)
        empty = pin.Model(loaded)
        empty.inertias[forearm] = loaded.inertias[forearm] - self.payload
        constraints = feeder.chain.constraint_models
        self.cases = (InertiaCase(empty, constraints), InertiaCase(pin.Model(loaded), constraints))
        self.index = feeder.index
        self.closure_frames = tuple(feeder.frame_id(name) for name in CLOSURE)
        joints = self.cases[1].data.joints
        self.motion_subspaces = {
            j: np.asarray(joints[j].S, dtype=float).reshape(6) for j in range(1, loaded.njoints)
        }

    def joint_rotations(self, q: np.ndarray) -> np.ndarray:
        """World orientation of the frames of ``cylinder_joint``, ``piston_joint``,
        ``arm_joint``, ``forearm_joint`` at every sample, shape (N, 4, 3, 3).

        Forward kinematics of the orientations, all samples at once, from the model's joint
        placements and axes (R_j = R_parent R_placement exp(θ_j ω_j), ω_j = 0 for a prismatic
        joint): the same numbers as Pinocchio's ``data.oMi[j].rotation``, without a
        per-sample Python call.

        Args:
            q: Configurations in paper order, shape (N, 4).
        """
        model = self.cases[1].model
        qp = self.to_pinocchio(np.asarray(q, dtype=float))
        world: dict[int, np.ndarray] = {0: np.eye(3)}
        for j in range(1, model.njoints):
            local = model.jointPlacements[j].rotation
            skew = pin.skew(self.motion_subspaces[j][3:])
            if np.any(skew):
                angle = qp[:, model.joints[j].idx_q][:, None, None]
                local = (
                    local
                    + np.sin(angle) * (local @ skew)
                    + (1.0 - np.cos(angle)) * (local @ skew @ skew)
                )
            world[j] = world[model.parents[j]] @ local
        return np.stack([world[j] for j in self.joint_ids], axis=1)

    def to_pinocchio(self, x: np.ndarray) -> np.ndarray:
        """Paper order (..., 4) → Pinocchio order."""
        return self.feeder.to_pinocchio(x)

    def to_paper(self, x: np.ndarray) -> np.ndarray:
        """Pinocchio order (..., 4) → paper order."""
        return self.feeder.to_paper(x)


@dataclass(frozen=True)
class SampledMotion:
    """A closed-chain motion that :func:`check_motion` has accepted; N ≥ 1 samples.

    Attributes:
        q, v, a: [φ1, r2, φ3, φ4] [rad, m] and their first and second time derivatives, paper
            order, float arrays of shape (N, 4).
        payload: 1 where the payload is gripped, else 0, int array of shape (N,).
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    payload: np.ndarray


@dataclass(frozen=True)
class ActuatorLoads:
    """Actuator loads and pin force along N samples (inverse dynamics of the closed chain).

    Attributes:
        motion: The motion the loads produce (checked).
        piston_force: Generalized force on ``piston_joint`` [N], positive along its axis
            (extending the cylinder), shape (N,) (Fig. 14).
        forearm_torque: Generalized force on ``forearm_joint`` [N·m], positive about its axis,
            shape (N,) (Fig. 15).
        closure_force: λ, the force [N] the arm exerts on the piston at the pin, world frame,
            shape (N, 3); the piston exerts −λ on the arm. Its z component is 0 by choice (see
            the module docstring).
    """

    motion: SampledMotion
    piston_force: np.ndarray
    forearm_torque: np.ndarray
    closure_force: np.ndarray

    def generalized_forces(self) -> np.ndarray:
        """Actuator generalized forces Sᵀ τ in paper order [0, F, 0, M], shape (N, 4)."""
        tau = np.zeros((self.piston_force.size, 4))
        tau[:, 1] = self.piston_force
        tau[:, 3] = self.forearm_torque
        return tau


def check_closure(feeder: Feeder, q: np.ndarray, what: str = "sample") -> None:
    """Raise :class:`UnreachablePoseError` unless every configuration closes the loop.

    Args:
        feeder: The device.
        q: Configurations in paper order, shape (N, 4), N ≥ 1.
        what: How the message names a configuration ("sample" → "sample 3").
    """
    residual = loop_residual(feeder, q)
    worst = int(np.argmax(residual))
    if residual[worst] > CLOSURE_TOLERANCE:
        name = f"{what} {worst}" if q.shape[0] > 1 else what
        raise UnreachablePoseError(
            f"{name} does not close the loop: pin gap {residual[worst]:.3e} m "
            f"> {CLOSURE_TOLERANCE:g} m at q = {np.round(q[worst], 6)}"
        )


def check_motion(
    dyn: FeederDynamics, q: np.ndarray, v: np.ndarray, a: np.ndarray, payload: np.ndarray
) -> SampledMotion:
    """Validate a sampled motion: float arrays (N, 4) ×3, N ≥ 1, and payload flags (N,).

    Raises:
        InputError: NaN/inf, wrong shapes, no samples, payload flags other than 0/1.
        UnreachablePoseError: A configuration that does not close the loop (eq. 44).
        SingularPoseError: A pose within 5° of the toggle.
    """
    arrays = []
    for name, value in (("q", q), ("v", v), ("a", a)):
        array = check_finite(name, value)
        if array.ndim != 2 or array.shape[1] != 4 or array.shape[0] == 0:
            raise InputError(
                f"{name} must have shape (N, 4), N ≥ 1, in paper order, got {array.shape}"
            )
        arrays.append(array)
    flags = check_finite("payload", payload)
    if flags.shape != (arrays[0].shape[0],) or any(x.shape != arrays[0].shape for x in arrays):
        raise InputError(
            f"q, v, a and payload must have N samples each, got shapes "
            f"{[x.shape for x in arrays]} and {flags.shape}"
        )
    if not np.all((flags == 0) | (flags == 1)):
        raise InputError(f"payload flags must be 0 or 1, got {np.unique(flags)}")
    check_closure(dyn.feeder, arrays[0])
    check_transmission(arrays[0])
    return SampledMotion(q=arrays[0], v=arrays[1], a=arrays[2], payload=flags.astype(int))


def inverse_dynamics(
    dyn: FeederDynamics, q: np.ndarray, v: np.ndarray, a: np.ndarray, payload: np.ndarray
) -> ActuatorLoads:
    """Piston force, forearm moment and pin force that produce a prescribed closed-chain motion.

    M q̈ + b comes from Pinocchio's RNEA (``rneaInParallel`` over the whole batch), the closure
    Jacobian from ``computeFrameJacobian`` of both pin frames (world-aligned) per sample; then
    the 3 × 3 systems of the module docstring are solved for all samples at once.

    Args:
        dyn: The device's dynamics models.
        q, v, a: [φ1, r2, φ3, φ4] and derivatives in paper order, shape (N, 4) each (closed
            loop, consistent velocities and accelerations, as from
            :func:`~feeder.cycle.feeding_cycle`).
        payload: 1 where the payload is gripped, else 0, shape (N,).

    Raises:
        InputError: Bad values or shapes, or velocities that violate the closure (|J q̇|).
        UnreachablePoseError: A configuration that does not close the loop.
        SingularPoseError: A pose within 5° of the toggle.
    """
    motion = check_motion(dyn, q, v, a, payload)
    v, payload = motion.v, motion.payload
    n = v.shape[0]
    qp, vp, ap = (dyn.to_pinocchio(x) for x in (motion.q, motion.v, motion.a))
    tree = np.empty((n, 4))  # M q̈ + b of the open tree, Pinocchio order
    jac_a = np.empty((n, 6, 4))
    jac_b = np.empty((n, 6, 4))
    frame_a, frame_b = dyn.closure_frames
    world = pin.LOCAL_WORLD_ALIGNED
    frame_jacobian = pin.computeFrameJacobian
    for start, stop, flag in payload_runs(payload):
        case = dyn.cases[flag]
        model, data = case.model, case.data
        tree[start:stop] = pin.rneaInParallel(
            1, case.pool, qp[start:stop].T, vp[start:stop].T, ap[start:stop].T
        ).T
        for k in range(start, stop):
            jac_a[k] = frame_jacobian(model, data, qp[k], frame_a, world)
            jac_b[k] = frame_jacobian(model, data, qp[k], frame_b, world)
    jac = dyn.to_paper(jac_a[:, :3] - jac_b[:, :3])  # (n, 3, 4) world rows, paper columns
    out_of_plane = float(np.abs(jac[:, 2]).max())
    if out_of_plane > PLANAR_TOLERANCE:
        raise InputError(
            f"the closure is not planar (|∂gap_z/∂q| = {out_of_plane:.3e}): the minimum-norm "
            "pin force of this module assumes a loop moving in the world x–y plane"
        )
    gap_rate = np.abs(np.einsum("nij,nj->ni", jac, v)).max(axis=1)
    worst = int(np.argmax(gap_rate))
    if gap_rate[worst] > VELOCITY_TOLERANCE:
        raise InputError(
            f"velocities at sample {worst} violate the closure: |J q̇| = {gap_rate[worst]:.3e} "
            f"m/s > {VELOCITY_TOLERANCE:g} m/s"
        )
    tree = dyn.to_paper(tree)
    # Rows φ1, r2, φ3: M q̈ + b = e_r2 τ_piston + J_xᵀ λx + J_yᵀ λy.
    system = np.zeros((n, 3, 3))
    system[:, 1, 0] = 1.0
    system[:, :, 1] = jac[:, 0, :3]
    system[:, :, 2] = jac[:, 1, :3]
    solution = np.linalg.solve(system, tree[:, :3, None])[..., 0]
    closure = np.column_stack([solution[:, 1:], np.zeros(n)])
    forearm = tree[:, 3] - np.einsum("ni,ni->n", jac[:, :, 3], closure)
    return ActuatorLoads(
        motion=motion,
        piston_force=solution[:, 0],
        forearm_torque=forearm,
        closure_force=closure,
    )
