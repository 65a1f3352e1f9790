"""The configuration rate q̇(q, v) of every joint type against Pinocchio's integrate."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from feeder.chain.kinematics.joints import ConfigurationRate

from .test_tree import every_joint_model

DIFFERENCE = 1e-8
"""Central difference (integrate(q, ±h v) over 2h, h = 1e-5) against the exact rate: truncation
h² ≈ 1e-10 of rates of order 1, round-off ε/h ≈ 1e-11; a wrong sign or factor is ~1."""


def test_the_rate_is_the_derivative_of_integrate():
    model = every_joint_model()
    rng = np.random.default_rng(11)
    h = 1e-5
    for _ in range(10):
        q = pin.integrate(model, pin.neutral(model), rng.uniform(-1.5, 1.5, model.nv))
        v = rng.uniform(-1.0, 1.0, model.nv)
        ahead, behind = pin.integrate(model, q, h * v), pin.integrate(model, q, -h * v)
        np.testing.assert_allclose(
            ConfigurationRate(model)(q, v), (ahead - behind) / (2.0 * h), atol=DIFFERENCE
        )
