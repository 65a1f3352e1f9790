"""∂M/∂q of any Pinocchio model (feeder.chain.dynamics.derivatives) against finite differences of
crba, on the feeder's open tree (revolute and prismatic joints) and the four-bar; bad models and
bad configurations are refused."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import load_closed_chain
from feeder.chain.dynamics.derivatives import mass_matrix_derivative
from feeder.exceptions import InputError

from ...conftest import robots_dir

FD_STEP = 1e-6
FD_RTOL = 1e-7
"""∂M/∂q by central differences of crba with h = 1e-6 (rad or m): round-off ~10 ε |M| / h ≈ 2e-9
|M|, truncation h² |M‴| / 6 ≈ 1e-12 |M|; compared relative to max |M|."""
STATES = 5
"""Random configurations per model."""
DIFFERENT = 1e-3
"""A derivative this large relative to max |M| [1/m or 1/rad] is real, not round-off."""


def sample_configurations(model: pin.Model, rng: np.random.Generator) -> np.ndarray:
    """STATES configurations inside the joint limits (clipped to ±3 where a limit is wide)."""
    low = np.maximum(model.lowerPositionLimit, -3.0)
    high = np.minimum(model.upperPositionLimit, 3.0)
    return rng.uniform(low, high, (STATES, model.nq))


@pytest.fixture(scope="module")
def fourbar_model(fourbar_urdf) -> pin.Model:
    """The four-bar's open tree (three revolute joints)."""
    return load_closed_chain(fourbar_urdf, [("rocker_tip", "ground_pin")]).model


@pytest.mark.parametrize("which", ["feeder", "fourbar"])
def test_mass_matrix_derivative_matches_finite_differences(which, feeder, fourbar_model, rng):
    """Entry (i, j·n + k) is ∂M_ij/∂q_k (the layout of the paper's eq. 4)."""
    model = {"feeder": feeder.model, "fourbar": fourbar_model}[which]
    data = model.createData()
    n = model.nv
    for q in sample_configurations(model, rng):
        exact = mass_matrix_derivative(model, data, q)
        assert exact.shape == (n, n * n)
        scale = np.max(np.abs(pin.crba(model, data, q)))
        for k, step in enumerate(FD_STEP * np.eye(n)):
            numeric = (pin.crba(model, data, q + step) - pin.crba(model, data, q - step)) / (
                2 * FD_STEP
            )
            numeric = np.triu(numeric) + np.triu(numeric, 1).T  # crba fills the upper triangle
            np.testing.assert_allclose(
                exact[:, k::n], numeric, rtol=0, atol=FD_RTOL * scale, err_msg=f"q_{k}"
            )


def test_the_feeder_mass_matrix_depends_on_its_configuration(feeder, rng):
    """A non-trivial check: ∂M/∂q of the feeder is not zero (M changes with φ1, r2, φ3, φ4)."""
    model = feeder.model
    q = sample_configurations(model, rng)[0]
    exact = mass_matrix_derivative(model, model.createData(), q)
    scale = np.max(np.abs(pin.crba(model, model.createData(), q)))
    assert np.max(np.abs(exact)) > DIFFERENT * scale


def test_bad_models_and_configurations_are_refused(feeder):
    continuous = pin.buildModelFromUrdf(
        str(robots_dir() / "double_pendulum_description/urdf/double_pendulum_continuous.urdf")
    )
    with pytest.raises(InputError, match="nq = 4, nv = 2"):
        mass_matrix_derivative(continuous, continuous.createData(), np.zeros(4))
    model, data = feeder.model, feeder.model.createData()
    with pytest.raises(InputError, match=r"shape \(4,\), got \(3,\)"):
        mass_matrix_derivative(model, data, np.zeros(3))
    with pytest.raises(InputError, match="finite"):
        mass_matrix_derivative(model, data, np.array([0.0, 0.3, np.nan, 0.0]))
    with pytest.raises(InputError, match="numeric"):
        mass_matrix_derivative(model, data, "0 0 0 0")
