"""Following a motion of the independent coordinates on one assembly branch: the first sample
(:func:`~feeder.chain.assembly.continuation.first_sample`), then the batched continuation for a
long motion (:mod:`feeder.chain.assembly.batch`), the sequential one
(:mod:`feeder.chain.assembly.continuation`) for a short motion or when a batched sample fails a
check — the same poses either way, to the Newton tolerance.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable

import numpy as np

from ...exceptions import InputError
from ...validation import check_finite, check_samples
from ..blas import one_blas_thread
from .batch import MIN_SAMPLES, BatchFallback, batch_track
from .continuation import first_sample, sequential
from .trajectory import Trajectory


@one_blas_thread
def track(
    partition,
    q_start: np.ndarray,
    x: np.ndarray,
    dx: np.ndarray | None = None,
    ddx: np.ndarray | None = None,
    branch: Callable[[np.ndarray], bool] | None = None,
    t: np.ndarray | None = None,
) -> Trajectory:
    """Follow a trajectory of the independent coordinates on one assembly branch.

    The first sample: ``q_start`` closed as it is (mounted if its loops are open, which picks the
    branch nearest to it), then its independent coordinates moved to ``x[0]`` by continuation —
    unless ``branch`` is given, which picks the first sample by
    :meth:`~feeder.chain.assembly.partition.Partition.assemble` from ``q_start`` instead. Each
    later sample starts Newton from the previous solution moved along the closure's tangent,
    which keeps the branch as long as the samples are fine compared with the distance to a
    singular pose; a pose near one is refused.

    Args:
        partition: The :class:`~feeder.chain.assembly.partition.Partition` of the chain.
        q_start: A pose (nq,) that picks the branch (the reference pose).
        x: Independent coordinates, (N, n_independent), columns in the order of the
            independent joints.
        dx, ddx: Their rates and accelerations (N, n_independent); zero if omitted.
        branch: Optional condition on the first sample's solution (``assemble``).
        t: The samples' times [s] (N,), named in the messages (else the samples' numbers).

    Returns:
        The motion: q (N, nq), v, a (N, nv), the velocity gain of every sample (N,).

    Raises:
        SingularPoseError: A sample at or near a singular pose, or the motion reaching one
            between two samples (a dead centre: the end of the independent joints' travel),
            named with its time and pose.
        UnreachablePoseError: The loops do not close at a sample, or a joint leaves its limits.
        InputError: Bad arrays; more independent joints than degrees of freedom.
    """
    n_ind = partition.independent.size
    x = check_samples("x", x, n_ind)
    dx = np.zeros_like(x) if dx is None else check_samples("dx", dx, n_ind)
    ddx = np.zeros_like(x) if ddx is None else check_samples("ddx", ddx, n_ind)
    if not x.shape == dx.shape == ddx.shape:
        raise InputError(f"x, dx, ddx must have one shape, got {x.shape}, {dx.shape}, {ddx.shape}")
    if t is not None:
        t = check_finite("t [s]", t)
        if t.shape != (x.shape[0],):
            raise InputError(f"t must give one time per sample ({x.shape[0]}), got {t.shape}")
    first = first_sample(partition, partition.chain.check_q(q_start), x[0], branch, t)
    if x.shape[0] >= MIN_SAMPLES:
        with contextlib.suppress(BatchFallback):  # then the sequential way, below
            return batch_track(partition, first, x, dx, ddx, t)
    return sequential(partition, first, x, dx, ddx, t)
