"""The self-stresses of closure Jacobians (feeder.chain.assembly.rank.self_stress_bases): the
unit vectors of the rows no joint moves where the other rows are independent, the singular value
decomposition elsewhere — compared with numpy's decomposition of each Jacobian (the same span:
equal orthogonal projectors)."""

from __future__ import annotations

import numpy as np

from feeder.chain.assembly.newton import RANK_TOLERANCE
from feeder.chain.assembly.rank import (
    GRAM_LIMIT,
    condition_bound,
    self_stress_bases,
    self_stresses,
)
from feeder.chain.kinematics.rows import closure_kinematics
from feeder.chain.kinematics.tree import tree_motion

from ..dynamics.fast_path_cases import motion_case

EPS = np.finfo(float).eps


def _svd_span(jac: np.ndarray) -> np.ndarray:
    """The projector (nc, nc) onto the null space of jacᵀ, from numpy's SVD."""
    u, s, _ = np.linalg.svd(jac, full_matrices=True)
    rank = int(np.sum(s > RANK_TOLERANCE * (np.abs(jac).max(initial=0.0) or 1.0)))
    return u[:, rank:] @ u[:, rank:].T


def _check(jacobians: np.ndarray) -> None:
    for jac, basis in zip(jacobians, self_stress_bases(jacobians), strict=True):
        assert np.allclose(basis @ basis.T, np.eye(basis.shape[0]), rtol=0.0, atol=1e-12)
        # the two projectors differ by round-off amplified by the conditioning of the rows
        # that move (σ_max / σ_min of the range of J): ε cond times a factor for the size
        s = np.linalg.svd(jac, compute_uv=False)
        kept = s[s > RANK_TOLERANCE * (np.abs(jac).max(initial=0.0) or 1.0)]
        cond = kept[0] / kept[-1] if kept.size else 1.0
        tolerance = 10.0 * jac.shape[0] * cond * EPS
        assert np.abs(basis.T @ basis - _svd_span(jac)).max() <= tolerance


def test_the_n_four_bars_self_stresses_are_its_out_of_plane_rows(tmp_path):
    chain, _, q, _, _ = motion_case("n_four_bar_10", tmp_path)
    jacobians = closure_kinematics(chain, tree_motion(chain.model, q)).jacobian
    _check(jacobians)
    for basis in self_stress_bases(jacobians):  # the fast path: the z rows' unit vectors
        rows = np.flatnonzero(basis.any(axis=0))
        assert basis.shape[0] == 10 and np.array_equal(basis[:, rows], np.eye(10))
        assert all(chain.row_labels()[r].endswith("z") for r in rows)


def test_bricard_and_the_delta_robot_match_the_decomposition(tmp_path):
    for name in ("bricard", "cad_robot_delta", "four_bar"):
        chain, _, q, _, _ = motion_case(name, tmp_path)
        _check(closure_kinematics(chain, tree_motion(chain.model, q)).jacobian)


def test_dependent_moving_rows_take_the_decomposition(rng):
    """Two moving rows equal up to 1e-12 (below the rank tolerance: dependent) beside a zero row:
    the Gram bound refuses them, and the decomposition finds two self-stresses, the zero row's
    and the difference of the two (the zero row's unit vector alone would be one)."""
    row = rng.normal(size=4)
    jac = np.vstack([row, row + 1e-12 * rng.normal(size=4), np.zeros(4), rng.normal(size=4)])
    gram = jac[[0, 1, 3]] @ jac[[0, 1, 3]].T
    assert np.linalg.cond(gram) > GRAM_LIMIT  # the case the bound must refuse
    basis = self_stresses(jac)
    assert basis.shape == (2, 4)
    assert np.allclose(basis.T @ basis, _svd_span(jac), rtol=0.0, atol=1e-9)


def test_no_closure_rows_no_self_stresses():
    assert [b.shape for b in self_stress_bases(np.zeros((2, 0, 3)))] == [(0, 0), (0, 0)]


def test_the_condition_bound_is_the_frobenius_condition_number():
    """condition_bound (the shared decomposition-free test of the load solve's shortcut, the
    self-stresses' Gram matrices and the batched continuation) is numpy's Frobenius condition
    number for square matrices (to round-off: a few products of O(1) sums), bounds the 2-norm
    one from above, and is infinite where the inverse is NaN or overflowed."""
    rng = np.random.default_rng(5)
    matrices = rng.normal(size=(4, 5, 5)) + 2.0 * np.eye(5)
    bound = condition_bound(matrices, np.linalg.inv(matrices))
    np.testing.assert_allclose(bound, np.linalg.cond(matrices, "fro"), rtol=1e-12)
    assert np.all(bound >= np.linalg.cond(matrices))
    broken = np.stack([np.full((5, 5), np.nan), np.full((5, 5), 1e300)])
    assert np.all(condition_bound(matrices[:2], broken) == np.inf)
