"""Inverse dynamics of the feeder's closed chain: the actuator loads and the pin force.

The open tree (:mod:`feeder.device.urdf_writer`) cut at the rod-eye pin moves as the closed
chain when the pin force λ acts on the piston at ``piston_pin`` and −λ on the arm at ``arm_pin``:

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
(:data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG`).

Samples with ``gripped == 0`` use the model without the payload (:mod:`feeder.dynamics.models`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..device.loop import check_closed, check_closed_velocity, check_transmission
from ..exceptions import InputError
from ..validation import check_flags, check_samples
from .models import FeederDynamics, gripped_runs

PLANAR_TOLERANCE = 1e-12
"""Largest accepted |∂(pin gap)_z/∂q| [m]: exactly zero for a planar loop (rotations about z)."""


@dataclass(frozen=True)
class SampledMotion:
    """A closed-chain motion that :func:`check_motion` has accepted; N ≥ 1 samples.

    Attributes:
        q, v, a: [φ1, r2, φ3, φ4] [rad, m] and their first and second time derivatives, paper
            order, float arrays of shape (N, 4).
        gripped: 1 where the payload is gripped, else 0, int array of shape (N,).
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    gripped: np.ndarray


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


def check_motion(
    dyn: FeederDynamics, q: np.ndarray, v: np.ndarray, a: np.ndarray, gripped: np.ndarray
) -> SampledMotion:
    """Validate a sampled motion: float arrays (N, 4) ×3, N ≥ 1, and grip flags (N,).

    Raises:
        InputError: NaN/inf, wrong shapes, no samples, grip flags other than 0/1, velocities
            that open the loop.
        UnreachablePoseError: A configuration that does not close the loop (eq. 44).
        SingularPoseError: A pose within 5° of the toggle.
    """
    what = "[φ1, r2, φ3, φ4] in paper order"
    q, v, a = (check_samples(name, x, 4, what) for name, x in (("q", q), ("v", v), ("a", a)))
    if not q.shape == v.shape == a.shape:
        raise InputError(
            f"q, v and a must have N samples each, got shapes {q.shape}, {v.shape}, {a.shape}"
        )
    flags = check_flags("gripped", gripped, q.shape[0])
    check_closed(dyn.feeder.params, q)
    check_closed_velocity(dyn.feeder.params, q, v)
    check_transmission(q)
    return SampledMotion(q=q, v=v, a=a, gripped=flags)


def actuator_loads(dyn: FeederDynamics, motion: SampledMotion) -> ActuatorLoads:
    """Piston force, forearm moment and pin force that produce a prescribed closed-chain motion.

    M q̈ + b comes from Pinocchio's RNEA (``rneaInParallel`` over the whole batch), the closure
    Jacobian from ``computeFrameJacobian`` of both pin frames (world-aligned) per sample; then
    the 3 × 3 systems of the module docstring are solved for all samples at once.

    Args:
        dyn: The device's dynamics models.
        motion: The closed-chain motion, checked by :func:`check_motion` (closed loop,
            consistent velocities, away from the toggle).

    Raises:
        InputError: A loop that is not planar.
    """
    v, gripped = motion.v, motion.gripped
    n = v.shape[0]
    qp, vp, ap = (dyn.to_pinocchio(x) for x in (motion.q, motion.v, motion.a))
    tree = np.empty((n, 4))  # M q̈ + b of the open tree, Pinocchio order
    jac_a = np.empty((n, 6, 4))
    jac_b = np.empty((n, 6, 4))
    frame_a, frame_b = dyn.closure_frames
    world = pin.LOCAL_WORLD_ALIGNED
    frame_jacobian = pin.computeFrameJacobian
    for start, stop, flag in gripped_runs(gripped):
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
