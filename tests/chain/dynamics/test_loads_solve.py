"""The load solve's fast path (feeder.chain.dynamics.loads_solve: the closure rows no joint moves
dropped, one inverse per sample, the decompositions skipped when every sample is square and well
conditioned) against the reference it replaces: the minimum-norm solution of the whole system
[Sᵀ Jᵀ] x = M q̈ + b from its pseudo-inverse (singular value decomposition), on the device, the
examples, the N-four-bar and the CAD exports."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain import ChainDynamics, inverse_dynamics
from feeder.chain.assembly.newton import RANK_TOLERANCE
from feeder.chain.dynamics.inverse import check_motion
from feeder.chain.dynamics.loads_solve import load_equations, solve_loads
from feeder.chain.dynamics.newton_euler import generalized_forces, joint_wrenches

from .fast_path_cases import NAMES, motion_case

EPS = np.finfo(float).eps


@pytest.mark.parametrize("name", NAMES)
def test_the_fast_load_solve_equals_the_pseudo_inverse_of_the_whole_system(name, tmp_path):
    chain, actuated, q, v, a = motion_case(name, tmp_path)
    dyn = ChainDynamics(chain, actuated)
    a = inverse_dynamics(dyn, q, v, a).accelerations  # with the idle motions' (CAD exports)
    q, v, a, motion, rows = check_motion(dyn, q, v, a)
    tau, lam = solve_loads(dyn, motion, rows)

    force, moment = joint_wrenches(chain.model, motion)
    rhs = generalized_forces(chain.model, motion, force, moment)
    system = load_equations(dyn, rows.jacobian)  # every closure row, zero columns included
    u, s, vt = np.linalg.svd(system, full_matrices=False)
    kept = s > RANK_TOLERANCE * s[:, :1]
    inverse = np.where(kept, 1.0 / np.where(kept, s, 1.0), 0.0)
    x = np.einsum("nji,nj->ni", vt, inverse * np.einsum("nji,nj->ni", u, rhs))
    n_act = len(actuated)
    reference = np.hstack([x[:, :n_act], x[:, n_act:] * dyn.row_scale])

    # both are backward-stable solutions of the same equations: their difference is bounded by
    # the condition number (σ_max over the smallest kept σ) times ε times the solution's size;
    # 10 nx covers the growth of the round-off with the matrix's size
    rank = kept.sum(axis=1)
    cond = float((s[:, 0] / s[np.arange(len(s)), rank - 1]).max())
    size = np.abs(reference).max()
    tolerance = 10.0 * system.shape[2] * cond * EPS * size
    assert np.abs(np.hstack([tau, lam]) - reference).max() <= tolerance
    still = ~np.any(rows.jacobian, axis=(0, 2))  # rows no joint moves: minimum norm is 0
    assert np.all(lam[:, still] == 0.0)
