"""Inverse dynamics of any closed chain: actuator loads, closure forces and every joint's reaction.

For a prescribed motion (q, q̇, q̈) of the open tree cut at the closures, the closed chain moves
when the closure forces λ act at the cuts and the actuators drive the named joints:

    M(q) q̈ + b(q, q̇) − Σ_e J_eᵀ w_e = Sᵀ τ + Jᵀ λ                      (one sample, nv rows)

* M q̈ + b are the tree's Newton–Euler forces (gravity from the model); w_e are the external
  wrenches on named frames, J_e their frame Jacobians;
* J (nc × nv) are the closure rows (:class:`~feeder.chain.model.closure.ClosedChain`), λ the forces
  conjugate to them: a force [N] on the body of ``frame_a`` at its origin for the point rows, a
  moment [N·m] for the rotation rows, and the opposite on the body of ``frame_b``;
* S selects the actuated joints' velocity components; τ are their generalized forces.

nv equations in n_act + nc unknowns, solved for all samples at once (:mod:`.loads_solve`). The
actuator loads must be determined (otherwise the actuation itself is singular:
:class:`SingularPoseError`) and the equations consistent (otherwise the actuated joints cannot
produce the motion: :class:`InputError`). Closure rows that repeat others (a planar loop) leave a
null space of statically indeterminate forces: the answer given is the one of minimum
‖K^(−1/2) λ‖, K the optional per-row stiffness (default 1: minimum norm, SI units) — the forces a
set of elastic supports of stiffness K would share — and those rows, and the reaction components
they change, are listed in :attr:`ChainLoads.indeterminacy` (:mod:`.indeterminacy`).

The reaction wrench of every joint of the tree is the wrench its parent exerts on its child,
world axes, moment about the joint's origin: the rate of momentum of the child's subtree less
gravity, the closure forces and the external wrenches acting on it (:mod:`.reactions`, by the
backward pass of :mod:`.newton_euler`: Newton–Euler over all samples at once, equal to
Pinocchio's RNEA to round-off), and the mount's: the wrench the base's support exerts on the
whole mechanism.

Data flow: :class:`ChainDynamics` → :func:`check_motion` (the tree's motion, the closure rows)
→ :mod:`.newton_euler` → :mod:`.loads_solve` → :mod:`.reactions` → :class:`ChainLoads`.

On a moving base (:class:`~feeder.chain.model.base.BaseMotion`: a slope, a ride, a hull table)
q, q̇, q̈ are the motion relative to the base, and every vector (reactions, closure forces, external
wrenches) is in the base's moving axes; the closure rows are the relative motion's and the
Newton–Euler passes take the absolute one (:func:`~feeder.chain.kinematics.tree.on_base`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ...validation import check_finite, check_samples
from ..assembly.partition import Partition
from ..blas import one_blas_thread
from ..kinematics.joints import kind_of
from ..kinematics.rows import ClosureKinematics, closure_kinematics
from ..kinematics.tree import TreeMotion, on_base, tree_motion
from ..model.base import BaseMotion, BaseState
from ..model.closure import ClosedChain
from ..model.forces import ForceElement
from .elements import BoundElements
from .idle import idle_accelerations, idle_basis
from .indeterminacy import Indeterminacy, PoseKinematics, indeterminacy, subsample
from .loads_solve import row_scale, solve_loads
from .newton_euler import held_wrench, joint_wrenches
from .reactions import (
    ClosureWrench,
    JointWrench,
    MountWrench,
    closure_wrenches,
    joint_reactions,
)

CLOSURE_TOLERANCE = 1e-9
"""Largest accepted closure residual [m, rad] of a prescribed configuration, and (per second,
per second²) of its velocity and acceleration rows: assembly closes loops to ~1e-13; 1e-9 leaves
room for motion data rounded to 9 digits."""

CONVENTION = (
    "statically indeterminate closure forces: minimum ‖K^(-1/2) λ‖ (K the per-row stiffness, "
    "default 1: minimum norm in SI units)"
)


@dataclass(frozen=True)
class ChainLoads:
    """Inverse dynamics of a closed chain along N samples.

    Attributes:
        actuators: Actuated joint name → its generalized force [N or N·m], (N,).
        closure_forces: λ, one column per closure row (:meth:`ClosedChain.row_labels`), (N, nc).
        closures: Closure label → :class:`ClosureWrench`.
        joints: Joint name → :class:`JointWrench` (every joint of the tree but a free-flyer,
            which transmits no wrench).
        convention: How indeterminate forces were chosen (:attr:`indeterminacy` says which).
        accelerations: q̈ (N, nv), the accelerations the loads belong to: the prescribed ones
            plus the idle motions' (:mod:`~feeder.chain.dynamics.idle`; equal to the prescribed
            ones when there is none).
        idle_motions: Number of idle motions (free with every actuated joint locked).
        elements: Force element name → its force (N,): a spring's or cylinder's tension [N]
            (positive pulls its frames together), a joint spring's resistance [N·m or N].
        mount: The wrench the mount exerts on the mechanism (:class:`MountWrench`).
        motion: The tree's motion (:class:`~feeder.chain.kinematics.tree.TreeMotion`) as the
            Newton–Euler pass took it: absolute, in the base's axes, idle included.
        gravity: Gravity [m/s²] in the same axes: the model's (3,), or (N, 3) on a moving base.
        base: The base's motion at the samples, or None for a base at rest.
        chain: The closed chain. q: The motion's configurations (N, nq).
        reach: The mechanism's size [m] (:attr:`Partition.length`), the moments' scale of
            :attr:`indeterminacy`; None: measured there.
        kinematics: The tree's placements and the closure rows at the samples of ``q`` that
            :func:`~.indeterminacy.subsample` picks (:class:`~.indeterminacy.PoseKinematics`),
            which :attr:`indeterminacy` reads; None: computed there (code that changes the
            samples, :func:`~.singular.spread`, drops them).
    """

    actuators: dict[str, np.ndarray]
    closure_forces: np.ndarray
    closures: dict[str, ClosureWrench]
    joints: dict[str, JointWrench]
    convention: str
    accelerations: np.ndarray
    idle_motions: int
    elements: dict[str, np.ndarray]
    mount: MountWrench
    motion: TreeMotion
    gravity: np.ndarray
    base: BaseState | None = None
    chain: ClosedChain | None = None
    q: np.ndarray | None = None
    reach: float | None = None
    kinematics: PoseKinematics | None = None

    @cached_property
    def indeterminacy(self) -> Indeterminacy:
        """The closure rows and the cuts' and joints' wrench components that a rigid model does
        not determine along the motion (:func:`~.indeterminacy.indeterminacy`; their values
        follow the convention :data:`CONVENTION`), computed when first asked (a few ms, which
        the device's many cycles need not spend)."""
        return indeterminacy(self.chain, self.q, self.reach, self.kinematics)

    def held_wrench(self, joint: int, inertia: pin.Inertia) -> tuple[np.ndarray, np.ndarray]:
        """The wrench joint ``joint``'s body exerts on a part it holds, of spatial ``inertia`` in
        the joint's frame (merged into the body's): force [N], moment [N·m] about the part's
        centre of gravity, (N, 3) each (:func:`~.newton_euler.held_wrench`)."""
        return held_wrench(self.motion, self.gravity, joint, inertia)


class ChainDynamics:
    """What the inverse dynamics of one chain needs that does not change along a motion.

    Args:
        chain: The closed chain (its model's gravity is used); a tree of any joints of
            :mod:`~feeder.chain.kinematics.joints`.
        actuated: Names of the actuated joints (one coordinate each: revolute, continuous,
            prismatic).
        stiffness: Optional closure label → per-row stiffness (rows of that closure), for the
            split of statically indeterminate forces; default 1 everywhere.
        elements: Force elements acting on the chain (:mod:`~feeder.chain.model.forces`).
        base: The base's prescribed motion (:class:`~feeder.chain.model.base.BaseMotion`),
            None for a base at rest.

    Raises:
        InputError: A joint type the dynamics do not handle (helical, ellipsoid, composite,
            mimic), an unknown or multi-coordinate actuated joint, a name given twice, a bad
            stiffness, a force element on an unknown frame or joint, a moving base without
            gravity or with a forward axis that is not horizontal.
    """

    def __init__(
        self,
        chain: ClosedChain,
        actuated: Sequence[str],
        stiffness: Mapping[str, Sequence[float]] | None = None,
        elements: Sequence[ForceElement] = (),
        base: BaseMotion | None = None,
    ):
        if not isinstance(chain, ClosedChain):
            raise InputError(
                f"chain must be a ClosedChain (the model and its closures), got {chain!r}"
            )
        if stiffness is not None and not isinstance(stiffness, Mapping):
            raise InputError(
                "stiffness must map closure labels to their rows' stiffness (a dict), got "
                f"{stiffness!r}"
            )
        if base is not None and not isinstance(base, BaseMotion):
            raise InputError(f"base must be a BaseMotion, got {base!r}")
        if base is not None and base.profiles:
            base.vehicle_axes(chain.model.gravity.linear)
        self.base = base if base is not None and base.profiles else None
        for j in range(1, chain.model.njoints):
            kind_of(chain.model.joints[j])
        self.columns = chain.coordinate_columns(actuated, "actuated").tolist()
        self.chain = chain
        self.actuated = tuple(actuated)
        self.row_scale = row_scale(chain, stiffness or {})
        self.data = chain.model.createData()
        self.elements = BoundElements(chain, elements)

    @cached_property
    def partition(self) -> Partition:
        """The chain with the actuated joints as its inputs (:class:`Partition`), built once."""
        return Partition(self.chain, self.actuated)

    def idle_count(self, q: np.ndarray) -> int:
        """Number of idle motions at the closed pose ``q`` with the actuated joints locked
        (:meth:`~feeder.chain.assembly.partition.Partition.idle_motions`; 0 when the locked
        mechanism can still move an origin: then it is under-actuated, which the load solve
        reports)."""
        try:
            return self.partition.idle_motions(q).shape[0]
        except SingularPoseError:
            return 0


def check_dynamics(dyn: ChainDynamics) -> None:
    """Refuse a ``dyn`` that is not a :class:`ChainDynamics`."""
    if not isinstance(dyn, ChainDynamics):
        raise InputError(
            "dyn must be a ChainDynamics (the chain with its actuated joints and force "
            f"elements), got {dyn!r}"
        )


def check_motion(
    dyn: ChainDynamics, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, TreeMotion, ClosureKinematics]:
    """q (N, nq), v, a (N, nv) as float arrays if they are a closed-chain motion, else raise;
    also returns the tree's batched motion and the closure rows along it.

    Raises:
        InputError: NaN/inf, shapes, velocities or accelerations that open the loops.
        UnreachablePoseError: A configuration that does not close the loops.
    """
    check_dynamics(dyn)
    model = dyn.chain.model
    q = check_samples("q", q, model.nq)
    v = check_samples("v", v, model.nv)
    a = check_samples("a", a, model.nv)
    if not q.shape[0] == v.shape[0] == a.shape[0]:
        raise InputError(f"q, v, a must have N samples each, got {q.shape}, {v.shape}, {a.shape}")
    motion = tree_motion(model, q, v, a)
    rows = closure_kinematics(dyn.chain, motion, v)
    for label, alignment in rows.hinge_alignment.items():
        if np.any(alignment < 0.0):
            k = int(np.argmax(alignment < 0.0))
            raise UnreachablePoseError(
                f"sample {k}: the revolute cut {label!r} is assembled with its two hinge axes "
                "opposite (upside down): not a closed configuration of the mechanism"
            )
    scale = np.maximum.reduce([np.ones(v.shape[0]), _row_peaks(v) ** 2, _row_peaks(a)])
    for what, values, limit, error in (
        ("configuration", rows.residual, np.ones_like(scale), UnreachablePoseError),
        ("velocities", rows.rate, np.sqrt(scale), InputError),
        ("accelerations", rows.acceleration, scale, InputError),
    ):
        worst = _row_peaks(values) / limit
        k = int(np.argmax(worst))
        if worst[k] > CLOSURE_TOLERANCE:
            if error is UnreachablePoseError:
                raise UnreachablePoseError(
                    f"sample {k} does not close the loops: residual {worst[k]:.3e} > "
                    f"{CLOSURE_TOLERANCE:g}"
                )
            raise InputError(
                f"the {what} of sample {k} open the loops ({worst[k]:.3e}): not a closed-chain "
                "motion (Partition.velocity / acceleration, feeder.chain.track give one)"
            )
    return q, v, a, motion, rows


def _row_peaks(values: np.ndarray) -> np.ndarray:
    """The largest magnitude in each row of ``values`` (N, k), (N,) (0 for k = 0), reduced
    along the samples of a transposed copy (numpy reduces a short last axis several times
    slower)."""
    return np.ascontiguousarray(np.abs(values).T).max(axis=0, initial=0.0)


def _external_terms(
    chain: ClosedChain, n: int, external: Mapping[str, np.ndarray]
) -> list[tuple[int, np.ndarray]]:
    """The checked external wrenches: (frame id, world wrench (N, 6) about the frame's origin)."""
    terms = []
    for name, wrench in external.items():
        frame = chain.frame_id(name)
        values = check_finite(f"external wrench on {name!r}", wrench)
        if values.shape == (6,):
            values = np.tile(values, (n, 1))
        if values.shape != (n, 6):
            raise InputError(
                f"external wrench on {name!r} must be (6,) or ({n}, 6), got {values.shape}"
            )
        terms.append((frame, values))
    return terms


@one_blas_thread
def inverse_dynamics(
    dyn: ChainDynamics,
    q: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
    external: Mapping[str, np.ndarray] | None = None,
    t: np.ndarray | None = None,
) -> ChainLoads:
    """Actuator loads, closure forces and every joint's reaction for a closed-chain motion.

    Args:
        dyn: The chain's dynamics (:class:`ChainDynamics`).
        q, v, a: Configurations (N, nq), velocities and accelerations (N, nv) of a closed-chain
            motion (checked: :func:`check_motion`).
        external: Optional external wrenches by frame name: world [force (3) N, moment (3) N·m
            about the frame's origin], (N, 6) or (6,) (constant).
        t: The samples' times [s], (N,): needed when a force element or the base's motion
            varies in time.

    Raises:
        InputError: Bad arrays, a motion that opens the loops, or one the actuated joints cannot
            produce.
        UnreachablePoseError: A configuration that does not close the loops.
        SingularPoseError: Actuator loads not determined by the equations (a singular
            actuation).
    """
    q, v, a, motion, rows = check_motion(dyn, q, v, a)
    picks = subsample(q.shape[0])
    kinematics = PoseKinematics(motion.at_rest(picks), rows.at(picks))
    terms = _external_terms(dyn.chain, q.shape[0], external or {})
    forces = {}
    t = _times(dyn, t, q.shape[0])
    if dyn.elements:
        element_terms, forces = dyn.elements.wrenches(motion, q, v, t)
        terms = terms + element_terms
    base = None
    if dyn.base is not None:
        base = dyn.base.state(t, dyn.chain.model.gravity.linear)
        motion = on_base(motion, base)
    count = dyn.idle_count(q[0])
    if count:
        basis = idle_basis(rows.jacobian, dyn.columns, count)
        a = a + idle_accelerations(dyn.chain.model, q, motion, basis, terms)
        motion = tree_motion(dyn.chain.model, q, v, a)
        if base is not None:
            motion = on_base(motion, base)
    wrenches = joint_wrenches(dyn.chain.model, motion, terms)  # the loads' and the reactions'
    tau, lam = solve_loads(dyn, motion, rows, wrenches)
    closures, closure_terms = closure_wrenches(dyn.chain, rows, lam)
    joints, mount = joint_reactions(
        dyn.chain, motion, closure_terms, None if base is None else base.rotation, wrenches
    )
    return ChainLoads(
        actuators={name: tau[:, i] for i, name in enumerate(dyn.actuated)},
        closure_forces=lam,
        closures=closures,
        joints=joints,
        convention=CONVENTION,
        accelerations=a,
        idle_motions=count,
        elements=forces,
        mount=mount,
        motion=motion,
        gravity=dyn.chain.model.gravity.linear if motion.gravity is None else motion.gravity,
        base=base,
        chain=dyn.chain,
        q=q,
        reach=dyn.partition.length,
        kinematics=kinematics,
    )


def _times(dyn: ChainDynamics, t: np.ndarray | None, n: int) -> np.ndarray:
    """The samples' times (N,) [s], checked; zeros when nothing varies in time."""
    if t is None:
        if dyn.elements.timed:
            raise InputError("a force element varies in time: give the samples' times t [s]")
        if dyn.base is not None and dyn.base.timed:
            raise InputError("the base moves: give the samples' times t [s]")
        return np.zeros(n)
    t = check_finite("t", t)
    if t.shape != (n,):
        raise InputError(f"t must have one time per sample, shape ({n},), got {t.shape}")
    dyn.elements.check_covers(float(t.min()), float(t.max()))
    return t
