"""The device's dynamics models: the open tree with and without the payload, each with its
closed-chain dynamics (:class:`~feeder.chain.ChainDynamics`, which gives the loads and every
reaction) and its constraint containers for ``constraintDynamics`` (the forward run).

The payload is gripped at the end of stage 1: samples with ``gripped == 0`` use a copy of the
model whose forearm body lacks the payload's spatial inertia (:func:`payload_inertia`), so the
loads step at the grip. No URDF is regenerated.

On a vehicle (:class:`~feeder.chain.BaseMotion`) the chain's dynamics take the base's motion as
the chain takes it: the model stands level and the base's state turns gravity and adds the hull's
motion at each sample. The forward run takes a slope only, as the model's gravity turned into the
tilted device's axes.
"""

from __future__ import annotations

import threading

import numpy as np
import pinocchio as pin

from ..chain import BAUMGARTE_RATE, BaseMotion, ChainDynamics, ClosedChain
from ..device.feeder import CLOSURE, PAPER_JOINTS, Feeder

ACTUATED_JOINTS = ("piston_joint", "forearm_joint")
"""The device's actuated joints: the hydraulic cylinder's piston and the rack-driven forearm."""

PAYLOAD_FRAME = "projectile"
"""Frame of the payload link (its centre of gravity, y = payload axis), fixed to the forearm."""

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

DYNAMICS_KEPT = 16
"""Most :class:`FeederDynamics` a thread keeps for reuse (:func:`feeder_dynamics`), as many as
the devices a process keeps (:func:`feeder.study.sweep.cached_feeder`)."""

_KEPT = threading.local()
"""Per thread (a Dask worker runs cases in threads, and the models' data are scratch space):
``kept``, (id(feeder), id(base)) → (feeder, base, their FeederDynamics), least recent first."""


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


def gripped_runs(gripped: np.ndarray) -> list[tuple[int, int, int]]:
    """Maximal runs of a constant grip flag: [(start, stop, flag)], stop exclusive."""
    gripped = np.asarray(gripped, dtype=int)
    edges = np.flatnonzero(np.diff(gripped)) + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges, [gripped.size]])
    return [(int(a), int(b), int(gripped[a])) for a, b in zip(starts, stops, strict=True)]


class InertiaCase:
    """One Pinocchio model of the device (with or without payload) and its reusable containers.

    Args:
        model: The open tree standing level (gravity −y).
        base: The vehicle's motion, None for standing level.
        gravity: The forward run's gravity [m/s²] (3,) on a slope (in the tilted device's axes),
            None for the model's.

    Attributes:
        model: The open tree of the forward run: ``model``, with ``gravity`` if given.
        data: Its data.
        constraint_models: The pin closure (``CONTACT_3D``, LOCAL frame of ``piston_pin``), a
            copy of the chain's with the Baumgarte corrector set
            (:meth:`~feeder.chain.ClosedChain.corrected_constraints`).
        constraint_datas: Their data, initialised for ``constraintDynamics``.
        prox: Proximal settings of ``constraintDynamics``.
        dynamics: The closed-chain dynamics (:class:`~feeder.chain.ChainDynamics`) of the
            level model with the pin closure, the piston and forearm joints actuated, on
            ``base``.
    """

    def __init__(
        self,
        model: pin.Model,
        base: BaseMotion | None = None,
        gravity: np.ndarray | None = None,
    ):
        chain = ClosedChain(model, [CLOSURE])
        self.dynamics = ChainDynamics(chain, ACTUATED_JOINTS, base=base)
        if gravity is not None:
            model = pin.Model(model)
            model.gravity = pin.Motion(np.asarray(gravity, dtype=float), np.zeros(3))
        self.model = model
        self.data = model.createData()
        # the generic run's Baumgarte rate ω (feeder.chain.simulate): critically damped, a loop
        # error decays in 1/ω = 50 ms; hω = 0.02 at 1 kHz is well inside the integrator's
        # stability region
        self.constraint_models, self.constraint_datas = chain.corrected_constraints(
            self.data, BAUMGARTE_RATE
        )
        self.prox = pin.ProximalSettings(
            PROXIMAL_ACCURACY, PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_MAX_ITERATIONS
        )


class FeederDynamics:
    """Everything the dynamics of one device needs that does not change along a cycle.

    Args:
        feeder: The device.
        base: The vehicle's motion (its forward axis
            :data:`~feeder.device.parameters.VEHICLE_FORWARD`), None for standing level.

    Attributes:
        feeder: The device.
        base: The vehicle's motion, or None.
        payload_inertia: Payload spatial inertia in the forearm joint frame
            (:func:`payload_inertia`).
        cases: (without payload, with payload): index it with the ``gripped`` flag.
        joint_ids: Pinocchio ids of ``cylinder_joint``, ``piston_joint``, ``arm_joint``,
            ``forearm_joint`` (paper order).
        index: Positions of [φ1, r2, φ3, φ4] in Pinocchio's v (``feeder.index``).
    """

    def __init__(self, feeder: Feeder, base: BaseMotion | None = None):
        self.feeder = feeder
        self.base = base
        loaded = pin.Model(feeder.model)
        tilt = None
        if base is not None and base.profiles and not base.timed:  # a slope: gravity turned
            tilt = base.state(np.zeros(1), loaded.gravity.linear).gravity[0]
        self.joint_ids = tuple(loaded.getJointId(name) for name in PAPER_JOINTS)
        forearm = self.joint_ids[3]
        self.payload_inertia = payload_inertia(feeder)
        empty = pin.Model(loaded)
        empty.inertias[forearm] = loaded.inertias[forearm] - self.payload_inertia
        self.cases = tuple(InertiaCase(model, base, tilt) for model in (empty, loaded))
        self.index = feeder.index

    def to_pinocchio(self, x: np.ndarray) -> np.ndarray:
        """Paper order (..., 4) → Pinocchio order."""
        return self.feeder.to_pinocchio(x)

    def to_paper(self, x: np.ndarray) -> np.ndarray:
        """Pinocchio order (..., 4) → paper order."""
        return self.feeder.to_paper(x)


def feeder_dynamics(feeder: Feeder, base: BaseMotion | None = None) -> FeederDynamics:
    """The :class:`FeederDynamics` of ``feeder`` on ``base``, built once per thread for the same
    two objects and reused: a sweep's or a design's cycles of one device and vehicle share its
    models, closures and partitions (building them took 2–4 ms of a 22 ms cycle). The key is the
    objects' identity: a Feeder is not changed once loaded and a BaseMotion is frozen; each is
    kept alive with its entry, so that its id is not reused. The :data:`DYNAMICS_KEPT` most
    recent are kept."""
    kept = _KEPT.__dict__.setdefault("kept", {})
    key = (id(feeder), id(base))
    entry = kept.pop(key, None) or (feeder, base, FeederDynamics(feeder, base))
    kept[key] = entry  # now the most recent
    while len(kept) > DYNAMICS_KEPT:
        del kept[next(iter(kept))]
    return entry[2]
