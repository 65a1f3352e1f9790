"""The block triangular inverse against LAPACK's dense one: permuted block triangular stacks,
dense ones, the N-four-bar's loads' equations, singular samples."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain import ChainDynamics
from feeder.chain.dynamics.block_inverse import _blocks, block_inverse
from feeder.chain.dynamics.inverse import check_motion
from feeder.chain.dynamics.loads_solve import load_equations

from .fast_path_cases import motion_case

ROUND_OFF = 1e-10
"""Both inverses of matrices with condition numbers below ~1e3 (diagonal blocks shifted by
3 I): relative round-off ~1e3 ε ≈ 1e-13 of entries of order 1; a wrong block is off by ~1."""


def block_triangular(rng, sizes, samples=5):
    """A stack of block lower triangular matrices with diagonal blocks of ``sizes`` and a
    random sparse lower part, its rows and columns shuffled; the blocks' sizes."""
    m = sum(sizes)
    matrices = np.zeros((samples, m, m))
    start = 0
    for size in sizes:
        here = slice(start, start + size)
        matrices[:, here, here] = rng.normal(size=(samples, size, size)) + 3.0 * np.eye(size)
        below = rng.random((size, start)) < 0.4
        matrices[:, here, :start] = rng.normal(size=(samples, size, start)) * below
        start += size
    return matrices[:, rng.permutation(m)][:, :, rng.permutation(m)]


@pytest.mark.parametrize("sizes", [(1,), (2, 2, 2), (1, 3, 2, 1), (4, 1, 1, 2, 3), (2,) * 20])
def test_block_triangular_stacks_match_the_dense_inverse(rng, sizes):
    matrices = block_triangular(rng, list(sizes))
    np.testing.assert_allclose(block_inverse(matrices), np.linalg.inv(matrices), atol=ROUND_OFF)
    blocks = _blocks(np.any(matrices != 0.0, axis=0).tobytes(), sum(sizes))
    assert max(rows.size for rows, _, _ in blocks) <= max(sizes)  # the form was found


def test_a_dense_stack_is_one_block(rng):
    matrices = rng.normal(size=(6, 7, 7)) + 3.0 * np.eye(7)
    np.testing.assert_allclose(block_inverse(matrices), np.linalg.inv(matrices), atol=ROUND_OFF)
    assert len(_blocks(np.ones((7, 7), bool).tobytes(), 7)) == 1


def test_the_n_four_bar_equations_are_two_by_two_blocks(tmp_path):
    """The N-four-bar's square loads' equations (its rows without the out-of-plane ones): N
    blocks of 2 (a loop's two forces) and one of 1 (the drive); the inverse is LAPACK's."""
    n = 10
    chain, actuated, q, v, a = motion_case(f"n_four_bar_{n}", tmp_path)
    dyn = ChainDynamics(chain, actuated)
    _, _, _, _, rows = check_motion(dyn, q, v, a)
    moved = np.any(rows.jacobian, axis=(0, 2))
    system = load_equations(dyn, rows.jacobian, moved)
    assert system.shape[1:] == (2 * n + 1, 2 * n + 1)
    blocks = _blocks(np.any(system != 0.0, axis=0).tobytes(), 2 * n + 1)
    assert sorted(rows.size for rows, _, _ in blocks) == [1] + [2] * n
    inverse = np.linalg.inv(system)
    scale = np.abs(inverse).max()
    np.testing.assert_allclose(block_inverse(system), inverse, atol=ROUND_OFF * scale)


def test_singular_samples_have_no_finite_inverse(rng):
    matrices = block_triangular(rng, [2, 1, 3])
    matrices[2] = 0.0
    matrices[2, :, 0] = 1.0  # every column but the first zero at this sample
    with np.errstate(all="ignore"):
        inverse = block_inverse(matrices)
    assert not np.isfinite(inverse[2]).all()
    others = [0, 1, 3, 4]
    np.testing.assert_allclose(inverse[others], np.linalg.inv(matrices[others]), atol=ROUND_OFF)
    structural = np.zeros((3, 4, 4))
    structural[:, :, :2] = rng.normal(size=(3, 4, 2))  # two columns only: no matching
    assert np.isnan(block_inverse(structural)).all()
