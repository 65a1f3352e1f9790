"""A forward run on a moving base: the hull's motion as a moving root (its fictitious forces),
the base's power and the absolute motion's energy.

The state (q, q̇) is the motion relative to the base (as in the inverse dynamics,
:mod:`~feeder.chain.dynamics.inverse`). In the base's moving axes the tree's equations keep the
mass matrix M(q) and the closure rows J of the relative motion; only the bias changes, to
b_B(q, q̇, t): the gravity, Coriolis and centrifugal terms of the absolute motion, which add the
fictitious forces (the base's acceleration, Euler's, the centrifugal and Coriolis forces of the
rotating axes) to the standing ones. b_B is Pinocchio's RNEA with q̈ = 0 on a copy of the tree
put on a moving root: a free-flyer carrying the base link, whose placement, velocity and
acceleration are the base's (:class:`~feeder.chain.model.base.BaseState`; the free-flyer's q̈ is
its body-axes rate, a₀ − Ω × v₀ and Ω̇), under the model's level gravity. Pinocchio's
``constraintDynamics`` solves the standing equations M q̈ + b = τ + Jᵀλ; it is given τ − b_B + b
(b its ``nonLinearEffects``), so that it solves

    M q̈ + b_B(q, q̇, t) = τ + Jᵀ λ.

The base's power: what the base's motion puts into the mechanism. The mount's wrench and the
loads (:class:`~feeder.chain.model.forces.Load`, applied in the base's axes) act on bodies whose
absolute velocity is the base's rigid velocity (v₀ + Ω × p) plus the relative one; the relative
part is in the run's work W, the rest is

    P_B = v₀ · F + Ω · M,      (F, M) = the mount's wrench plus the loads', about the origin
                                       = Σ (rate of momentum − gravity) of every body,

all in the base's moving axes: the moving root's generalized force in the RNEA with the run's q̈.
Internal forces (drives, springs, dampers, cylinders, the closure forces) act in pairs whose
absolute power is their relative power. Hence the balance of the absolute motion

    T_abs(t) + V(t) − T_abs(t₀) − V(t₀) = W(t) + W_B(t),     W_B = ∫ P_B dt,

T_abs the kinetic energy of the absolute motion (the base link's included), V the gravitational
energy in the level axes (−Σ m g · x_G) plus the elastic energy. It holds for a base motion
whose channels are consistent (each value's rate its rate column, each rate's its acceleration):
the profiles' are; a hull table interpolated linearly between its rows is only as consistent as
its rows are dense.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.base import BaseMotion, BaseState


class MovingBase:
    """The hull's terms of one chain's forward equations (module docstring): the tree on a
    moving root.

    Args:
        model: The chain's Pinocchio model (its gravity is the standing, level one).
        base: The base's prescribed motion.
    """

    def __init__(self, model: pin.Model, base: BaseMotion):
        self.model, self.base = model, base
        self.gravity = np.array(model.gravity.linear)
        self.axes = base.vehicle_axes(self.gravity)
        rooted = pin.Model()
        rooted.gravity = model.gravity
        root = rooted.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
        rooted.appendBodyToJoint(root, model.inertias[0], pin.SE3.Identity())
        for j in range(1, model.njoints):  # ids shift by one: the root is joint 1
            joint = rooted.addJoint(
                model.parents[j] + 1, model.joints[j], model.jointPlacements[j], model.names[j]
            )
            rooted.appendBodyToJoint(joint, model.inertias[j], pin.SE3.Identity())
        self.rooted, self.data = rooted, rooted.createData()
        self._roots: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def prepare(self, t: np.ndarray) -> None:
        """Compute the moving root's motion at the times t [s] (N,) in one pass, for
        :meth:`bias` to take at those times: a run's output samples, or the times its next
        step evaluates the equations at (:func:`stage_times`). The base's state at one time
        costs 5 × the rest of an evaluation (numpy's overhead on its many small arrays; 140 µs
        against 30 µs on the device, measured), at 15 times hardly more than at one."""
        self._roots = {}
        if t.size:  # none for an implicit method's step (stage_times)
            q0, v0, a0 = self.roots(self.states(t))
            self._roots = {time: (q0[k], v0[k], a0[k]) for k, time in enumerate(t.tolist())}

    def states(self, t: np.ndarray) -> BaseState:
        """The base's motion at the times t [s], (N,)."""
        return self.base.state(np.asarray(t, dtype=float), self.gravity, self.axes)

    @staticmethod
    def roots(base: BaseState) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The moving root's q (N, 7), q̇ and q̈ (N, 6) at the N samples of ``base``; q̈ is the
        free-flyer's body-axes rate: a₀ − ω × v₀ and α."""
        turn = np.array([pin.Quaternion(r).coeffs() for r in base.rotation]).reshape(-1, 4)
        rate = base.acceleration - np.cross(base.omega, base.velocity)
        return (
            np.hstack([base.position, turn]),
            np.hstack([base.velocity, base.omega]),
            np.hstack([rate, base.alpha]),
        )

    def root(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The moving root's q (7,), q̇ and q̈ (6,) at time t [s] (:meth:`roots`): prepared
        (:meth:`prepare`), or computed alone at a time that was not."""
        root = self._roots.get(t)
        if root is None:
            root = tuple(x[0] for x in self.roots(self.states(np.array([t]))))
        return root

    def bias(
        self, data: pin.Data, t: float, q: np.ndarray, v: np.ndarray
    ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The correction b − b_B (nv,) that turns the standing equations' τ into the moving
        base's (module docstring), and the rooted tree's state at time t [s] with q̈ = 0 (for
        :meth:`power`)."""
        q0, v0, a0 = self.root(t)
        state = (
            np.concatenate([q0, q]),
            np.concatenate([v0, v]),
            np.concatenate([a0, np.zeros_like(v)]),
        )
        moving = pin.rnea(self.rooted, self.data, *state)[6:]
        return pin.nonLinearEffects(self.model, data, q, v) - moving, state

    def power(self, state: tuple[np.ndarray, np.ndarray, np.ndarray], a: np.ndarray) -> float:
        """P_B [W] (module docstring) at the rooted state of :meth:`bias` and q̈ = a (nv,)."""
        rooted_q, rooted_v, rooted_a = state
        rooted_a[6:] = a
        wrench = pin.rnea(self.rooted, self.data, rooted_q, rooted_v, rooted_a)[:6]
        return float(wrench @ rooted_v[:6])

    def energies(self, t: np.ndarray, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        """The kinetic energy of the absolute motion and the gravitational energy in the level
        axes [J], (N,) each, every body's (the base link's too), at the times t [s] (N,) and
        relative states q (N, nq), v (N, nv)."""
        q0, v0, _ = self.roots(self.states(t))
        kinetic, potential = np.empty(t.size), np.empty(t.size)
        for k in range(t.size):
            rooted_q = np.concatenate([q0[k], q[k]])
            kinetic[k] = pin.computeKineticEnergy(
                self.rooted, self.data, rooted_q, np.concatenate([v0[k], v[k]])
            )
            potential[k] = pin.computePotentialEnergy(self.rooted, self.data, rooted_q)
        return kinetic, potential


def stage_times(solver) -> np.ndarray:
    """The times [s] at which SciPy's explicit Runge–Kutta solver (DOP853, RK45) evaluates the
    equations in its next step if the step it proposes is accepted: t + c h for its tableau's
    nodes c and the step's end (and DOP853's three dense-output stages), with h formed as
    SciPy's step control forms it (its proposed length, at most ``max_step``, cut at the end
    of the run). Empty for the implicit methods (their stages' times depend on the Newton
    iterations). A rejected step, or another version of SciPy that forms h otherwise,
    evaluates at other times: :meth:`MovingBase.bias` computes those alone."""
    nodes = getattr(solver, "C", None)
    if nodes is None:
        return np.zeros(0)
    t = solver.t
    end = t + min(solver.h_abs, solver.max_step) * solver.direction
    if solver.direction * (end - solver.t_bound) > 0:
        end = solver.t_bound
    h = end - t  # as SciPy forms it (rounded through the end time)
    extra = getattr(solver, "C_EXTRA", np.zeros(0))
    return t + np.concatenate([nodes[1:], [1.0], extra]) * h
