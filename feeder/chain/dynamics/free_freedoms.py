"""Freedoms that the actuated joints leave free and that carry mass, and the pose they rest in.

With every actuated joint locked a closed chain may still move (:func:`~feeder.chain.assembly.
rank.locked_motions`: the null space of [J; S], J the closure rows, S the actuated joints' rows).
The kinematics accept such a motion when it moves no joint origin, frame or centre of gravity
(an *idle motion*: a rod spinning about the line through its two balls,
:data:`~feeder.chain.assembly.rank.IDLE_TOLERANCE`); the rest of the locked motions move points.
Among those, a *free freedom* is one that moves mass — its kinetic energy per unit rate,
½ nᵀ M n, is not zero beyond round-off: the eigenvalues of Fᵀ M F (F an orthonormal basis of the
point-moving locked motions) above :data:`~feeder.chain.dynamics.idle.INERTIA_RANK` of the mass
matrix's largest entry, the tolerance the inverse dynamics already use to tell an idle motion
that moves no mass (:mod:`~feeder.chain.dynamics.idle`). A rod whose centre of gravity lies off
the line through its balls is one: gravity swings it, the motion table does not say where it is,
and a hybrid run (:mod:`~feeder.chain.dynamics.hybrid`) integrates it forward.

Its start: the pose at rest (:func:`rest_pose`): the free freedoms moved, with the actuated joints
held and the loops closed, to a minimum of the potential energy (gravity, the model's or a
moving base's tilted one, and the force elements' elastic energy) — SciPy's BFGS from the pose
given (a local minimum: the basin it starts in), then SciPy's ``root`` on the stationarity
condition (the potential's gradient has no component along any locked motion), which the
minimiser, working on energy values, meets only to about √ε of the energy's size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import UnreachablePoseError
from ..assembly.newton import POSITION_TOLERANCE, newton
from ..assembly.rank import IDLE_TOLERANCE, locked_motions, moved_joints, rank_tolerance
from ..kinematics.pose import ChainPose
from ..mobility import localised
from .idle import INERTIA_RANK


@dataclass(frozen=True)
class FreeFreedoms:
    """The free freedoms of a chain at one pose (module docstring), m of them (m may be 0).

    Attributes:
        basis: An orthonormal basis (m, nv) of the joint rates that move them.
        motions: The same span, each row with a unit entry at its own pivot joint's rate and zeros
            at the other pivots' (:func:`~feeder.chain.mobility.localised`), (m, nv).
        pivots: The velocity index of each freedom's pivot joint, (m,): the joint whose rate
            measures it.
        joints: For each freedom, the joints it moves, largest share first.
    """

    basis: np.ndarray
    motions: np.ndarray
    pivots: np.ndarray
    joints: tuple[tuple[str, ...], ...]

    def __len__(self) -> int:
        """The number m of free freedoms."""
        return self.basis.shape[0]


def free_freedoms(dyn, q: np.ndarray) -> FreeFreedoms:
    """The free freedoms (module docstring) of ``dyn``'s chain at the closed pose ``q`` (nq,)
    with its actuated joints locked (``dyn``: a
    :class:`~feeder.chain.dynamics.inverse.ChainDynamics`)."""
    chain, model = dyn.chain, dyn.chain.model
    pose = ChainPose(chain, q)
    jac = pose.jacobian
    tolerance = rank_tolerance(jac)
    rank, locked = locked_motions(jac, dyn.partition.dependent, tolerance)
    nothing = FreeFreedoms(
        np.zeros((0, model.nv)), np.zeros((0, model.nv)), np.zeros(0, dtype=int), ()
    )
    # The actuated joints must be free to move, their columns in the range of the others' (at a
    # singular pose, a dead centre, they are not, and the locked motion that appears there is
    # no freedom of the mechanism): the whole Jacobian has the rank of the others' columns.
    if locked.shape[0] == 0 or np.linalg.matrix_rank(jac, tol=tolerance) > rank:
        return nothing
    _, s, vt = np.linalg.svd(pose.point_rows() @ locked.T, full_matrices=False)
    moving = vt[s > IDLE_TOLERANCE * dyn.partition.length] @ locked
    if moving.shape[0] == 0:
        return nothing
    mass = pin.crba(model, model.createData(), pose.q)
    mass = np.triu(mass) + np.triu(mass, 1).T  # crba fills the upper triangle
    energy, vectors = np.linalg.eigh(moving @ mass @ moving.T)
    carrying = energy > INERTIA_RANK * float(np.abs(mass).max())
    basis = vectors[:, carrying].T @ moving
    if basis.shape[0] == 0:
        return nothing
    motions, pivots = localised(basis)
    joints = tuple(moved_joints(model, motion) for motion in motions)
    return FreeFreedoms(basis, motions, pivots, joints)


def rest_pose(
    dyn, q: np.ndarray, free: FreeFreedoms, t: float, gravity: np.ndarray | None = None
) -> np.ndarray:
    """The pose at rest of the free freedoms ``free`` near the closed pose ``q`` (nq,) (module
    docstring): the actuated joints and every coordinate the free freedoms leave alone as in
    ``q``, the force elements taken at time ``t`` [s], under ``gravity`` [m/s²] (3,) in the
    model's axes (None: the model's; a moving base's tilts it); (nq,), its revolute angles wrapped
    (:meth:`~feeder.chain.assembly.partition.Partition.wrap`: the minimiser may wind one past
    a turn on its way).

    Raises:
        UnreachablePoseError: The loops do not close along the way (the free freedoms run into
            a singular pose before they come to rest).
    """
    chain, model = dyn.chain, dyn.chain.model
    weighed = model  # the model whose gravity weighs the pose
    if gravity is not None:
        weighed = pin.Model(model)
        weighed.gravity = pin.Motion(np.asarray(gravity, dtype=float), np.zeros(3))
    data = weighed.createData()
    dependent = dyn.partition.dependent
    zero = np.zeros(model.nv)

    def pose(s: np.ndarray) -> np.ndarray:
        moved, gap = newton(chain, pin.integrate(model, q, s @ free.basis), dependent)
        if gap > POSITION_TOLERANCE * 1e3:
            raise UnreachablePoseError(
                f"the free freedoms ({', '.join(free.joints[0])}, …) cannot come to rest: the "
                f"loops open by {gap:.3e} on their way (a singular pose)"
            )
        return moved

    def potential(s: np.ndarray) -> float:
        moved = pose(s)
        return pin.computePotentialEnergy(weighed, data, moved) + dyn.elements.energy(moved)

    def stationarity(s: np.ndarray) -> np.ndarray:
        moved = pose(s)
        gradient = pin.computeGeneralizedGravity(weighed, data, moved).copy()
        if dyn.elements:
            gradient -= dyn.elements.generalized(moved, zero, t)[0]
        jac = chain.jacobian(moved)
        _, locked = locked_motions(jac, dependent, rank_tolerance(jac))
        return free.basis @ (locked.T @ (locked @ gradient))

    start = np.zeros(len(free))
    import scipy.optimize  # here: only a rest search loads it

    basin = scipy.optimize.minimize(potential, start, method="BFGS").x
    polished = scipy.optimize.root(stationarity, basin, method="hybr")
    return dyn.partition.wrap(pose(polished.x if polished.success else basin))
