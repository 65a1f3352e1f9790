"""The result of following a motion on one assembly branch
(:func:`~feeder.chain.assembly.tracking.track`): the whole chain's motion and its velocity gain at
every sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...exceptions import InputError


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A closed-chain motion, N samples; its arrays are read-only.

    Attributes:
        q: Configurations (N, nq), every loop closed, dependent revolute angles wrapped.
        v: Velocities (N, nv), J q̇ = 0, minimum norm in the idle motions.
        a: Accelerations (N, nv), J q̈ + J̇ q̇ = 0, minimum norm in the idle motions (the
            dynamics add the idle motions' own: :mod:`feeder.chain.dynamics.idle`).
        gain: The velocity gain at every sample (N,) [–]
            (:mod:`feeder.chain.assembly.partition`).
        batched: Whether the batched continuation (:mod:`feeder.chain.assembly.batch`) gave the
            samples; False for the sequential one (a short motion, or a batched sample that
            failed a check).

    Raises:
        InputError: Arrays of different lengths.
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    gain: np.ndarray
    batched: bool = False

    def __post_init__(self):
        n = self.q.shape[0]
        if not self.v.shape[0] == self.a.shape[0] == self.gain.shape[0] == n:
            raise InputError(
                f"q, v, a, gain must have one row per sample, got {self.q.shape}, "
                f"{self.v.shape}, {self.a.shape}, {self.gain.shape}"
            )
        for array in (self.q, self.v, self.a, self.gain):
            array.setflags(write=False)

    def __len__(self) -> int:
        """The number of samples N."""
        return self.q.shape[0]
