"""The result of a forward run (:func:`~feeder.chain.dynamics.forward.simulate`) on the
caller's time grid, with its checks: the drift, the energy balance, the tracking error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_finite
from ..kinematics.joints import angle_columns, angular_difference
from .inverse import ChainLoads
from .singular import SingularPass


@dataclass(frozen=True)
class ForwardRun:
    """A forward run on the caller's time grid.

    Attributes:
        t: Times [s], (N,).
        q: Configurations, (N, nq) (projected onto the constraints).
        v: Velocities, (N, nv). a: Accelerations, (N, nv).
        loads: The inverse dynamics of the sampled motion: the drive loads (the applied ones),
            closure forces, every joint's reaction, every force element's force.
            ``a``, ``loads``, ``energy`` and ``kinetic`` are None for a run asked for its
            motion alone (``simulate(..., loads=False)``).
        residual: Closure residual [m, rad] of each sample before its projection, (N,): the drift.
        energy: Kinetic, gravitational and elastic energy [J], (N,).
        kinetic: Kinetic energy [J], (N,).
        work: Work of the non-conservative forces since t[0] [J], (N,) (their power relative
            to the base on a moving base).
        steps: Accepted integration steps. evaluations: Right-hand sides evaluated.
        projections: Steps projected back onto the constraints.
        singular: The singular positions the run passed (closure rank drops,
            :class:`~feeder.chain.dynamics.singular.SingularPass`), in time order; empty for a
            run that stops at them.
        indeterminate: Samples whose loads are unbounded or indeterminate (bool (N,)): near a
            singular position, where the loads' equations have a condition number above
            :data:`~feeder.chain.dynamics.loads_solve.MAX_FORCE_GAIN`; their loads in
            :attr:`loads` are zero, not values.
        controller: A :class:`~.forward_equations.Controller`'s states x at the samples,
            (N, n_states); (N, 0) for an actuation without states.
        actuation: The applied actuation u, the actuated joints' generalized forces [N or N·m],
            (N, n_actuated) (zero without actuation).
        base_work: On a moving base, the work [J] the base's motion has done on the mechanism
            since t[0], (N,) (:mod:`~feeder.chain.dynamics.forward_base`); None on a base at
            rest. :attr:`energy` and :attr:`kinetic` are then the absolute motion's, and
            :attr:`loads` ``.mount`` the base's support on the mechanism at every sample.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray | None
    loads: ChainLoads | None
    residual: np.ndarray
    energy: np.ndarray | None
    kinetic: np.ndarray | None
    work: np.ndarray
    steps: int
    evaluations: int
    projections: int
    singular: tuple[SingularPass, ...] = ()
    indeterminate: np.ndarray | None = None
    controller: np.ndarray | None = None
    actuation: np.ndarray | None = None
    base_work: np.ndarray | None = None

    def drift(self) -> float:
        """Largest closure residual over the run before projection [m, rad]."""
        return float(self.residual.max())

    def balance(self) -> np.ndarray:
        """E(t) − E(t₀) − W(t) [J], (N,), less the base's work W_B(t) on a moving base: zero
        for an exact run.

        Raises:
            InputError: A run asked for its motion alone (no energies).
        """
        if self.energy is None:
            raise InputError(
                "the run was asked for its motion alone (loads=False): it has no energies"
            )
        balance = self.energy - self.energy[0] - self.work
        return balance if self.base_work is None else balance - self.base_work

    def energy_error(self) -> float:
        """Largest |E(t) − E(t₀) − W(t)| [J] (:meth:`balance`)."""
        return float(np.abs(self.balance()).max())

    def energy_scales(self) -> dict[str, float]:
        """The energies [J] the run moves, against which its balance is measured: the largest
        kinetic energy, |work| and |change of the potential (gravitational and elastic)
        energy| over the run, and the round-off of the total energy (ε max |E|, the floor)."""
        self.balance()  # refuses a run without energies
        potential = self.energy - self.kinetic
        return {
            "kinetic energy": float(self.kinetic.max()),
            "|work|": float(np.abs(self.work).max()),
            **(
                {}
                if self.base_work is None
                else {"|base's work|": float(np.abs(self.base_work).max())}
            ),
            "|change of potential energy|": float(np.abs(potential - potential[0]).max()),
            "round-off of the energy": float(np.finfo(float).eps * np.abs(self.energy).max()),
        }

    def displacement(self, model: pin.Model) -> float:
        """Largest |q(t) ⊖ q(t₀)| over the run and the velocity components [rad, m]
        (:meth:`tracking` against the first sample)."""
        return float(self.tracking(model, np.tile(self.q[0], (self.t.size, 1))).max())

    def tracking(self, model: pin.Model, q_reference: np.ndarray) -> np.ndarray:
        """Largest |q ⊖ q_reference| of every velocity component over the run, (nv,) (a
        revolute angle wrapped by a turn, a quaternion of opposite sign, count as equal)."""
        reference = check_finite("q_reference", q_reference)
        if reference.shape != self.q.shape:
            raise InputError(f"q_reference must have shape {self.q.shape}, got {reference.shape}")
        angles = angle_columns(model)
        pairs = zip(reference, self.q, strict=True)
        gaps = [angular_difference(model, r, q, angles) for r, q in pairs]
        return np.abs(np.array(gaps)).max(axis=0)
