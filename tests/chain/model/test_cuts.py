"""Every cut kind of the registry, one formula each: the per-sample rows (Pinocchio's data, one
sample) equal the batched rows (the tree's motion, many samples), and both are the derivatives
they claim to be (finite differences of the residual and of the Jacobian); the reaction wrench
is the one the rows' forces do work through; a kind added to the registry is read everywhere."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain import ClosedChain, Closure, load_mechanism, read_spec
from feeder.chain.dynamics.reactions import closure_wrenches
from feeder.chain.kinematics.rows import closure_kinematics, cut_frames
from feeder.chain.kinematics.tree import tree_motion
from feeder.chain.model.closure import as_closure
from feeder.chain.model.cuts import KINDS, PointCut, RevoluteCut, WeldCut, register
from feeder.chain.readers.urdf import build_model
from feeder.exceptions import InputError

from ...conftest import REPO
from ..kinematics.test_tree import frame_jacobian
from .test_closure import SPATIAL

SAMPLES = 6

STEP = 1e-6
"""Central-difference step [rad, m]: truncation error ~h² ≈ 1e-12 for unit curvatures (the
spatial branches are under a metre, the rates of order 1), round-off ~ε/h ≈ 1e-10."""
FD_TOLERANCE = 1e-8
"""Analytic against central-difference derivatives: above both error terms of :data:`STEP`."""
ROUND_OFF = 1e-12
"""Per-sample against batched rows: the same formulas on frames from two computations
(Pinocchio's, the numpy recursion) that agree to a few ulps on a ~1 m mechanism."""

AXIS, AXIS_B = (0.2, 0.3, 0.9), (-0.1, 0.5, 0.8)
"""A slanted cut axis, given differently in the two frames (both normalised by the closure)."""


@pytest.fixture(scope="module", params=sorted(KINDS))
def chain(request) -> ClosedChain:
    """The two spatial branches of test_closure, their tips cut with each registered kind."""
    closure = Closure("tip", "tip2", request.param, axis=AXIS, axis_b=AXIS_B)
    return ClosedChain(build_model(SPATIAL, "<spatial>"), [closure])


def states(chain: ClosedChain, rng) -> tuple[np.ndarray, np.ndarray]:
    """Random configurations and velocities (SAMPLES, nv) (one coordinate per joint)."""
    n = chain.model.nv
    return rng.uniform(-1.0, 1.0, (SAMPLES, n)), rng.uniform(-1.0, 1.0, (SAMPLES, n))


@pytest.mark.parametrize("count", [SAMPLES, 1], ids=["batch", "one-sample-batch"])
def test_rows_per_sample_are_the_batched_rows(chain, count, rng):
    """Residual, Jacobian and bias J̇ q̇ of one cut: ClosedChain's per-sample methods (arrays
    without a sample axis) against closure_kinematics over ``count`` samples (a batch of one
    takes the products' one-vector calls on (1, …) arrays); q̈ = 0, so its accelerations are the
    bias."""
    q, v = (x[:count] for x in states(chain, rng))
    rows = closure_kinematics(chain, tree_motion(chain.model, q, v, np.zeros_like(v)), v)
    for k in range(count):
        np.testing.assert_allclose(rows.residual[k], chain.residual(q[k]), atol=ROUND_OFF)
        np.testing.assert_allclose(rows.jacobian[k], chain.jacobian(q[k]), atol=ROUND_OFF)
        np.testing.assert_allclose(rows.acceleration[k], chain.bias(q[k], v[k]), atol=ROUND_OFF)
    (cut,) = chain.cuts
    assert rows.jacobian.shape == (count, cut.rows, chain.model.nv) and chain.nc == cut.rows


def test_rows_are_the_derivatives_of_the_residual(chain, rng):
    """∂(residual)/∂q by central differences against residual_jacobian, per sample and batched
    (the cut's residual_jacobian on the batched frames), and J̇ q̇ against the derivative of J q̇
    along q + t q̇."""
    q, v = states(chain, rng)
    (cut,) = chain.cuts
    eye = np.eye(chain.model.nv)
    for k in range(SAMPLES):
        numeric = np.column_stack(
            [
                (chain.residual(q[k] + STEP * e) - chain.residual(q[k] - STEP * e)) / (2 * STEP)
                for e in eye
            ]
        )
        np.testing.assert_allclose(chain.residual_jacobian(q[k]), numeric, atol=FD_TOLERANCE)
        rate = (
            (chain.jacobian(q[k] + STEP * v[k]) - chain.jacobian(q[k] - STEP * v[k]))
            @ v[k]
            / (2 * STEP)
        )
        np.testing.assert_allclose(chain.bias(q[k], v[k]), rate, atol=FD_TOLERANCE)
    (a, b), motion = chain.frame_ids[0], tree_motion(chain.model, q)
    batched = cut.residual_jacobian(
        cut_frames(chain.model, motion, [(a, b)], [np.arange(chain.model.nv)], True, False)
    )
    for k in range(SAMPLES):
        np.testing.assert_allclose(batched[k], chain.residual_jacobian(q[k]), atol=ROUND_OFF)


def test_the_wrench_does_the_work_of_the_row_forces(chain, rng):
    """The cut's wrench (f, m) on body a at frame a's origin, and its opposite on body b at frame
    b's, deliver the generalized forces Jᵀ λ of the row forces λ: J_aᵀ w − J_bᵀ w = Jᵀ λ."""
    q, v = states(chain, rng)
    rows = closure_kinematics(chain, tree_motion(chain.model, q, v), v)
    lam = rng.normal(size=(SAMPLES, chain.nc))
    (wrench,), terms = closure_wrenches(chain, rows, lam)
    (a, w_a), (b, w_b) = terms
    np.testing.assert_array_equal(w_a, -w_b)
    motion = tree_motion(chain.model, q)
    delivered = np.einsum("nkv,nk->nv", frame_jacobian(chain.model, motion, a), w_a) + np.einsum(
        "nkv,nk->nv", frame_jacobian(chain.model, motion, b), w_b
    )
    np.testing.assert_allclose(
        delivered, np.einsum("nkv,nk->nv", rows.jacobian, lam), atol=ROUND_OFF
    )


def test_alignment_is_the_cosine_of_the_cut_axes(chain, rng):
    """A kind with an alignment test (revolute: u_a · u_b) gives it batched and per sample
    (reversed_hinges); the others have none."""
    q, _ = states(chain, rng)
    rows = closure_kinematics(chain, tree_motion(chain.model, q))
    (cut,), (a, b) = chain.cuts, chain.frame_ids[0]
    if not isinstance(cut, RevoluteCut):
        assert rows.hinge_alignment == {}
        return
    for k in range(SAMPLES):
        chain.residual(q[k])
        u_a = chain.data.oMf[a].rotation @ np.array(chain.closures[0].axis)
        u_b = chain.data.oMf[b].rotation @ np.array(chain.closures[0].axis_b)
        assert abs(rows.hinge_alignment[cut.label][k] - u_a @ u_b) <= ROUND_OFF
        assert chain.reversed_hinges() == ([cut.label] if u_a @ u_b < 0.0 else [])


def test_kinds_are_the_registry():
    """Closures, their row counts and the readers' lists come from the registry: one class per
    kind, registered under its name."""
    assert KINDS == {"point": PointCut, "weld": WeldCut, "revolute": RevoluteCut}
    for kind, cls in KINDS.items():
        assert cls.kind == kind
        assert Closure("a", "b", kind).rows == len(cls.labels)


class BallCut(PointCut):
    """A kind a user might add: a ball joint's rows under other labels."""

    kind = "ball"
    labels = ("x", "y", "z")


def test_a_registered_kind_is_read_everywhere(monkeypatch, tmp_path):
    """Registering a kind makes the closures, the side-file reader and the chain take it."""
    monkeypatch.setitem(KINDS, "ball", BallCut)  # undone after the test
    assert register(BallCut) is BallCut and KINDS["ball"] is BallCut
    assert as_closure(Closure("a", "b", "ball")).rows == 3
    example = (REPO / "examples" / "four_bar" / "closures.toml").read_text(encoding="utf-8")
    (tmp_path / "four_bar.urdf").write_bytes(
        (REPO / "examples" / "four_bar" / "four_bar.urdf").read_bytes()
    )
    side = tmp_path / "closures.toml"
    side.write_text(example.replace('type = "revolute"', 'type = "ball"'), encoding="utf-8")
    chain = load_mechanism(read_spec(side))
    assert isinstance(chain.cuts[0], BallCut)
    assert chain.row_labels() == [f"coupler_tip-rocker_tip:{x}" for x in "xyz"]
    side.write_text(example.replace('type = "revolute"', 'type = "hinge"'), encoding="utf-8")
    with pytest.raises(InputError, match=r"one of \['ball', 'point', 'revolute', 'weld'\]"):
        read_spec(side)
