"""Pinocchio's analytic derivatives of the constrained dynamics on the feeder vs differences.

pin.computeConstraintDynamicsDerivatives(model, data, cmodels, cdatas, settings), called right
after constraintDynamics at the same (q, v, τ), returns ∂q̈/∂q, ∂q̈/∂v, ∂q̈/∂τ, ∂λ_c/∂q, ∂λ_c/∂v,
∂λ_c/∂τ. They are compared with central differences of constraintDynamics itself, and ∂q̈/∂τ,
∂λ/∂τ also with the hand-derived Lagrange system (feeder.paper.lagrange), which is linear in τ.

Finding (Pinocchio 4.1.0): for a loop closure between two moving joints (joint1_id > 0 and
joint2_id > 0, the feeder's pin), the column of the FIRST velocity index of ∂λ_c/∂q (and here
of ∂q̈/∂q) is wrong; every other column and the v- and τ-derivatives are right. The first index
is the arm_joint in the feeder's model. It is not specific to the feeder: with an unrelated
pendulum joint put first (pin.appendModel), all the feeder's columns agree with the differences
and only the pendulum's — whose true derivatives are zero — is wrong. ``test_first_column``
keeps this visible (strict xfail: it fails loudly once Pinocchio is fixed). Likely cause, found
in review: Pinocchio 4.1's ``contact-info.hxx`` constructs ``loop_span_indexes`` with nv zeros and
``init()`` then appends the real indices, so the derivative loop adds column 0's term nv extra
times; the column-0 error was measured to grow exactly in proportion to nv (nv = 7, 10, 16) on a
minimal spatial loop. World-anchored contacts (joint2_id = 0) are not affected.

Tolerance: steps h_q = 1e-5 [rad, m], h_v = 1e-3 [rad/s, m/s] (q̈ and λ are quadratic in v:
central differences are exact up to round-off), h_τ = 1 [N, N·m] (linear). Errors, relative to
the largest entry of each matrix: truncation (h_q / 0.2 m)² ≈ 3e-9; round-off and the proximal
solver's residual (~1e-13 relative, it converges to machine precision here) divided by h:
≲ 1e-8. DERIVATIVE_RTOL = 1e-6 leaves a factor 100 and still catches any wrong term (the broken
column is off by O(1)).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.device.feeder import PAPER_JOINTS
from feeder.device.loop import loop_state

from ..paper.helpers import forward_dynamics

PROXIMAL = pin.ProximalSettings(1e-14, 1e-8, 50)
"""Accuracy 1e-14, mu 1e-8, ≤ 50 iterations: the solver's residual stays far below the
differences' truncation (module docstring)."""
STEPS = {"q": 1e-5, "v": 1e-3, "tau": 1.0}
"""Central-difference steps [rad or m, rad/s or m/s, N or N·m] (module docstring)."""
DERIVATIVE_RTOL = 1e-6
"""Relative to each matrix's largest entry: truncation ~3e-9 plus round-off / h ≲ 1e-8, with
a factor 100 left; the broken column is off by O(1) (module docstring)."""
LAGRANGE_RTOL = 1e-8
"""∂q̈/∂τ and ∂λ/∂τ from the Lagrange KKT vs Pinocchio: two solves of the same system."""
PAPER_STATES = (  # φ3 [rad], φ4 [rad], φ̇3 [rad/s], φ̇4 [rad/s], F [N], τ4 [N·m]
    (0.3, 0.5, 0.7, -0.9, 1500.0, 30.0),
    (1.2, -1.1, -0.4, 1.3, 2500.0, -12.0),
    (1.6, 0.2, 0.9, 0.2, 800.0, 5.0),
)


class ConstrainedModel:
    """A Pinocchio model carrying the feeder, its pin closure and constrained dynamics."""

    def __init__(self, feeder, model: pin.Model):
        self.model, self.data = model, model.createData()
        closure = feeder.chain.constraint_models[0]
        names = [feeder.model.names[closure.joint1_id], feeder.model.names[closure.joint2_id]]
        self.cmodels = pin.StdVec_RigidConstraintModel()
        self.cmodels.append(
            pin.RigidConstraintModel(
                pin.ContactType.CONTACT_3D,
                model,
                model.getJointId(names[0]),
                closure.joint1_placement,
                model.getJointId(names[1]),
                closure.joint2_placement,
                pin.ReferenceFrame.LOCAL,
            )
        )
        self.cdatas = pin.StdVec_RigidConstraintData()
        self.cdatas.append(self.cmodels[0].createData())
        pin.initConstraintDynamics(model, self.data, self.cmodels, self.cdatas)
        self.index = np.array([model.joints[model.getJointId(n)].idx_v for n in PAPER_JOINTS])

    def forward(self, q, v, tau):
        a = pin.constraintDynamics(
            self.model, self.data, q, v, tau, self.cmodels, self.cdatas, PROXIMAL
        )
        assert PROXIMAL.iter < PROXIMAL.max_iter
        return a.copy(), self.data.lambda_c.copy()

    def analytic(self, q, v, tau):
        self.forward(q, v, tau)
        return dict(
            zip(
                ("a_q", "a_v", "a_tau", "l_q", "l_v", "l_tau"),
                (
                    np.array(x)
                    for x in pin.computeConstraintDynamicsDerivatives(
                        self.model, self.data, self.cmodels, self.cdatas, PROXIMAL
                    )
                ),
                strict=True,
            )
        )

    def central_differences(self, q, v, tau):
        out = {}
        for name, step in STEPS.items():
            a_cols, l_cols = [], []
            for k in range(self.model.nv):
                dx = np.zeros(self.model.nv)
                dx[k] = step
                args_plus = {"q": q, "v": v, "tau": tau}
                args_minus = dict(args_plus)
                args_plus[name], args_minus[name] = args_plus[name] + dx, args_minus[name] - dx
                (a_p, l_p), (a_m, l_m) = self.forward(**args_plus), self.forward(**args_minus)
                a_cols.append((a_p - a_m) / (2 * step))
                l_cols.append((l_p - l_m) / (2 * step))
            out[f"a_{name}"], out[f"l_{name}"] = np.stack(a_cols, 1), np.stack(l_cols, 1)
        return out


@pytest.fixture(scope="module")
def plain(feeder):
    return ConstrainedModel(feeder, feeder.model)


@pytest.fixture(scope="module")
def with_leading_joint(feeder):
    """The feeder behind an unrelated pendulum joint that takes velocity index 0."""
    pendulum = pin.Model()
    joint = pendulum.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "pendulum_joint")
    pendulum.appendBodyToJoint(
        joint, pin.Inertia(1.0, np.array([0.0, 0.1, 0.0]), 0.01 * np.eye(3)), pin.SE3.Identity()
    )
    model = pin.appendModel(pendulum, feeder.model, 0, pin.SE3.Identity())
    model.gravity = feeder.model.gravity
    return ConstrainedModel(feeder, model)


def _state(feeder, system, sample):
    """Assembled (q, v, τ) in the system's order, from a PAPER_STATES row."""
    phi3, phi4, dphi3, dphi4, force, torque = sample
    loop = loop_state(feeder.params, phi3, phi4, rates=(dphi3, dphi4))
    q, v, tau = (
        np.full(system.model.nv, 0.2),
        np.full(system.model.nv, -0.3),
        np.zeros(system.model.nv),
    )
    q[system.index] = loop.q
    v[system.index] = loop.v
    tau[system.index] = [0.0, force, 0.0, torque]
    return q, v, tau


def _assert_close(analytic, difference, columns, label):
    scale = np.max(np.abs(difference))
    error = np.max(np.abs(analytic[:, columns] - difference[:, columns]))
    assert error <= DERIVATIVE_RTOL * scale, f"{label}: {error:.3e} vs scale {scale:.3e}"


@pytest.mark.parametrize("sample", PAPER_STATES)
def test_velocity_and_torque_derivatives(feeder, plain, sample):
    q, v, tau = _state(feeder, plain, sample)
    analytic, difference = plain.analytic(q, v, tau), plain.central_differences(q, v, tau)
    for key in ("a_v", "l_v", "a_tau", "l_tau"):
        _assert_close(analytic[key], difference[key], slice(None), key)


@pytest.mark.parametrize("sample", PAPER_STATES)
def test_configuration_derivatives_except_first_column(feeder, plain, sample):
    q, v, tau = _state(feeder, plain, sample)
    analytic, difference = plain.analytic(q, v, tau), plain.central_differences(q, v, tau)
    for key in ("a_q", "l_q"):
        _assert_close(analytic[key], difference[key], slice(1, None), key)


@pytest.mark.parametrize("sample", PAPER_STATES)
def test_all_feeder_columns_behind_a_leading_joint(feeder, with_leading_joint, sample):
    system = with_leading_joint
    q, v, tau = _state(feeder, system, sample)
    analytic, difference = system.analytic(q, v, tau), system.central_differences(q, v, tau)
    for key in analytic:
        _assert_close(analytic[key], difference[key], system.index, key)


@pytest.mark.xfail(
    strict=True,
    reason="Pinocchio 4.1: wrong first column of ∂λ_c/∂q for a "
    "loop closure between two moving joints (see the module docstring)",
)
def test_first_column(feeder, plain):
    q, v, tau = _state(feeder, plain, PAPER_STATES[0])
    analytic, difference = plain.analytic(q, v, tau), plain.central_differences(q, v, tau)
    _assert_close(analytic["l_q"], difference["l_q"], slice(0, 1), "l_q")


@pytest.mark.parametrize("sample", PAPER_STATES)
def test_torque_derivatives_match_lagrange(feeder, plain, sample):
    """q̈ and λ are affine in τ: ∂/∂τ_k = (forward(τ + e_k) − forward(τ)) exactly in theory,
    evaluated with the hand-derived system and mapped onto Pinocchio's convention."""
    p = feeder.params
    q, v, tau = _state(feeder, plain, sample)
    analytic = plain.analytic(q, v, tau)
    rotation = plain.cdatas[0].oMc1.rotation
    qp, vp, taup = (feeder.to_paper(x) for x in (q, v, tau))
    base_a, base_l = forward_dynamics(p, qp, vp, taup)
    for k in range(4):
        a_k, l_k = forward_dynamics(p, qp, vp, taup + np.eye(4)[k])
        column = plain.index[k]
        expected_a = feeder.to_paper(analytic["a_tau"][:, column])
        expected_l = -rotation[:2, :] @ analytic["l_tau"][:, column]
        scale_a = np.max(np.abs(feeder.to_paper(analytic["a_tau"])))
        scale_l = np.max(np.abs(analytic["l_tau"]))
        np.testing.assert_allclose(a_k - base_a, expected_a, rtol=0, atol=LAGRANGE_RTOL * scale_a)
        np.testing.assert_allclose(l_k - base_l, expected_l, rtol=0, atol=LAGRANGE_RTOL * scale_l)
