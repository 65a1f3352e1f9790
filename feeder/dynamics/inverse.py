"""Inverse dynamics of the feeder's closed chain: the actuator loads and the pin force.

The open tree (:mod:`feeder.device.urdf_writer`) cut at the rod-eye pin moves as the closed
chain when the pin force λ acts on the piston at ``piston_pin`` and −λ on the arm at ``arm_pin``:

    M(q) q̈ + b(q, q̇) = Sᵀ τ_act + Jᵀ λ                                          (cf. eq. 46)

* M q̈ + b (inertia, Coriolis and gravity, −y) are the open tree's Newton–Euler forces;
* J = ∂(p_piston_pin − p_arm_pin)/∂q is the closure's world-frame Jacobian (3 × 4), so Jᵀ λ is
  the generalized force of the pin force pair;
* S selects the actuated coordinates: the piston force on r2 (``piston_joint``) and the forearm
  moment on φ4 (``forearm_joint``); φ1 and φ3 are passive (zero generalized force).

Four equations, five unknowns (τ_piston, τ_forearm, λx, λy, λz), rank four: the closed chain's
inverse dynamics (:func:`feeder.chain.inverse_dynamics`) does the work, and gives every joint's
reaction with the loads (:mod:`feeder.dynamics.reactions` names them). The loop is planar: the
cylinder and arm pivots turn about world z and the piston slides in the x–y plane, so the z row of
J vanishes identically and λz drops out of the equations. The out-of-plane pin force is
**statically indeterminate** in the rigid model: any pair ±λz along the pin axis is balanced by
bending moments in the cylinder's and the arm's pivots, which carry moments about x and y. In the
machine it is shared by the rod-eye bearing, the cylinder trunnions and the arm bearing according
to their axial stiffness, play and misalignment; rigid-body mechanics cannot tell. We report the
minimum-norm answer λz = 0 (the generic solver's convention; it flags the row as indeterminate):
the arm–frame joint then carries the whole out-of-plane load of the arm, forearm and payload
(stages 1–2 swing the forearm in the horizontal plane), and the piston and cylinder carry none of
it (on a tilted or moving base, only their own out-of-plane weight and inertia). The equations are
singular at the toggle (transmission angle 0° or 180°), which is refused
(:data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG`).

Samples with ``gripped == 0`` use the model without the payload (:mod:`feeder.dynamics.models`):
each run of a constant grip flag is one call of the chain's inverse dynamics, and
:class:`ActuatorLoads` is the paper-named view over their results
(:class:`~feeder.chain.results.ChainLoads`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..chain import inverse_dynamics
from ..chain.results import BaseState, ChainLoads
from ..device.loop import check_closed, check_closed_velocity, check_transmission
from ..exceptions import InputError
from ..validation import check_flags, check_samples
from .models import ACTUATED_JOINTS, FeederDynamics, gripped_runs


@dataclass(frozen=True)
class SampledMotion:
    """A closed-chain motion that :func:`check_cycle_motion` has accepted; N ≥ 1 samples.

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
class LoadRun:
    """The chain's inverse dynamics of one run of samples with a constant grip flag.

    Attributes:
        samples: The run's samples in the motion.
        gripped: Its grip flag (which model: ``FeederDynamics.cases[gripped]``).
        loads: The chain's loads, closure forces, joint reactions and mount there
            (:class:`~feeder.chain.results.ChainLoads`; joints by their URDF names, world axes).
    """

    samples: slice
    gripped: int
    loads: ChainLoads


@dataclass(frozen=True)
class ActuatorLoads:
    """Actuator loads and pin force along N samples (inverse dynamics of the closed chain): the
    paper's names over the chain's results, run by run of the grip flag.

    Attributes:
        motion: The motion the loads produce (checked).
        runs: The chain's inverse dynamics of each run of a constant grip flag, in order
            (:class:`LoadRun`); :func:`~feeder.dynamics.reactions.pin_reactions` reads the
            joints' reactions there.

    On a vehicle every vector is in the device's axes as they move with the hull.
    """

    motion: SampledMotion
    runs: tuple[LoadRun, ...]

    def joined(self, read: Callable[[ChainLoads], np.ndarray]) -> np.ndarray:
        """A quantity of the chain's results over all N samples: ``read`` of each run's
        :class:`~feeder.chain.results.ChainLoads`, the runs' rows one after the other."""
        parts = [read(run.loads) for run in self.runs]
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    @cached_property
    def piston_force(self) -> np.ndarray:
        """Generalized force on ``piston_joint`` [N], positive along its axis (extending the
        cylinder), (N,) (Fig. 14)."""
        return self.joined(lambda loads: loads.actuators[ACTUATED_JOINTS[0]])

    @cached_property
    def forearm_torque(self) -> np.ndarray:
        """Generalized force on ``forearm_joint`` [N·m], positive about its axis, (N,)
        (Fig. 15)."""
        return self.joined(lambda loads: loads.actuators[ACTUATED_JOINTS[1]])

    @cached_property
    def closure_force(self) -> np.ndarray:
        """λ, the force [N] the arm exerts on the piston at the pin, (N, 3); the piston exerts
        −λ on the arm. Its z component is 0 by choice (module docstring)."""
        return self.joined(lambda loads: loads.closure_forces)

    @cached_property
    def base(self) -> BaseState | None:
        """The base's motion at the samples (None: standing level)."""
        if self.runs[0].loads.base is None:
            return None
        return BaseState(
            *(
                self.joined(lambda loads, f=f: getattr(loads.base, f.name))
                for f in dataclasses.fields(BaseState)
            )
        )

    def generalized_forces(self) -> np.ndarray:
        """Actuator generalized forces Sᵀ τ in paper order [0, F, 0, M], shape (N, 4)."""
        tau = np.zeros((self.piston_force.size, 4))
        tau[:, 1] = self.piston_force
        tau[:, 3] = self.forearm_torque
        return tau


def check_cycle_motion(
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


def actuator_loads(
    dyn: FeederDynamics, motion: SampledMotion, t: np.ndarray | None = None
) -> ActuatorLoads:
    """Piston force, forearm moment and pin force that produce a prescribed closed-chain motion,
    with every joint's reaction.

    The closed chain's inverse dynamics (:func:`feeder.chain.inverse_dynamics`) of the device's
    model (with or without the payload, by the grip flag), all samples of a run at once, on the
    vehicle's motion ``dyn.base``.

    Args:
        dyn: The device's dynamics models.
        motion: The closed-chain motion, checked by :func:`check_cycle_motion` (closed loop,
            consistent velocities, away from the toggle).
        t: The samples' times [s], (N,): needed on a moving base.

    Raises:
        InputError: Times that are not one per sample, or none on a moving base.
    """
    n = motion.q.shape[0]
    if t is not None and np.shape(t) != (n,):
        raise InputError(f"t must have one time per sample, shape ({n},), got {np.shape(t)}")
    qp, vp, ap = (dyn.to_pinocchio(x) for x in (motion.q, motion.v, motion.a))
    runs = []
    for start, stop, flag in gripped_runs(motion.gripped):
        run = slice(start, stop)
        times = None if t is None else t[run]
        loads = inverse_dynamics(dyn.cases[flag].dynamics, qp[run], vp[run], ap[run], t=times)
        runs.append(LoadRun(run, flag, loads))
    return ActuatorLoads(motion=motion, runs=tuple(runs))
