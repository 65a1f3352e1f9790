"""The retrofit payload (feeder.study.retrofit): checked on the Pinocchio model of the retrofit
device against the original, not on the parameters alone."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.device.feeder import load_feeder
from feeder.exceptions import InputError
from feeder.study.retrofit import retrofit

MASS_FACTOR = 1.2
LENGTH_FACTOR = 1.15
CG_FRACTION = 0.4
"""The payload's CG stays at 40 % of its length from its base, which the tray holds in place."""
FK_ATOL = 1e-14
"""Two forward-kinematics runs of models that differ in one fixed offset: positions of < 2 m to
a few ε, times ~10 for the composed joint placements."""
MASS_RTOL = 1e-14
"""Masses and moments: the URDF writes the parameters' floats exactly (repr), Pinocchio merges
the payload into the forearm body by one addition, so a few ε of the sums."""
SAMPLE_STRIDE = 25
"""Every 25th sample of the cycle for the per-sample forward kinematics."""


@pytest.fixture(scope="module")
def retrofit_feeder(feeder):
    return load_feeder(retrofit(feeder.params, MASS_FACTOR, LENGTH_FACTOR))


@pytest.mark.parametrize(
    "factors", [(0.0, 1.1), (-1.2, 1.1), (1.2, 0.0), (1.2, -1.0), (1e306, 1.0), (1.0, 1e-4)]
)
def test_non_positive_or_absurd_factor_raises(feeder, factors):
    with pytest.raises(InputError, match=r"positive, within 0.001…1000"):
        retrofit(feeder.params, *factors)


@pytest.mark.parametrize("factors", [(np.nan, 1.1), (1.2, np.inf), ("1.2", 1.1)])
def test_non_numeric_factor_raises(feeder, factors):
    with pytest.raises(InputError, match="retrofit (mass|length) factor"):
        retrofit(feeder.params, *factors)


def test_payload_mass_scales_exactly(feeder, retrofit_feeder):
    """In the parameters, and in the Pinocchio model: the forearm body (with the payload merged
    in) gains exactly (factor − 1) payload masses, the other bodies are unchanged."""
    old, new = feeder.params.payload, retrofit_feeder.params.payload
    assert new.mass == old.mass * MASS_FACTOR
    gained = np.array([i.mass for i in retrofit_feeder.model.inertias]) - np.array(
        [i.mass for i in feeder.model.inertias]
    )
    forearm = feeder.model.getJointId("forearm_joint")
    expected = np.zeros_like(gained)
    expected[forearm] = (MASS_FACTOR - 1.0) * old.mass
    np.testing.assert_allclose(
        gained, expected, rtol=0, atol=MASS_RTOL * feeder.model.inertias[forearm].mass
    )


def test_payload_moments_scale_with_mass_and_length(feeder, retrofit_feeder):
    """Transverse moments (about forearm x and z) as m L², the axial one (y) as m."""
    old, new = feeder.params.payload.moments, retrofit_feeder.params.payload.moments
    transverse = MASS_FACTOR * LENGTH_FACTOR**2
    np.testing.assert_allclose(
        new, (old[0] * transverse, old[1] * MASS_FACTOR, old[2] * transverse), rtol=MASS_RTOL
    )


def test_payload_cg_moves_along_forearm_y(feeder, retrofit_feeder, cycle):
    """At every pose of a cycle, Pinocchio's placement of the payload frame in the retrofit
    device is the original's moved by 0.4 ΔL along the forearm's y axis, not rotated."""
    length = feeder.params.payload_length
    shift = CG_FRACTION * (LENGTH_FACTOR - 1.0) * length
    assert retrofit_feeder.params.payload_length == LENGTH_FACTOR * length
    placements = {}
    for name, device in (("old", feeder), ("new", retrofit_feeder)):
        model, data = device.model, device.model.createData()
        frame, forearm = device.frame_id("projectile"), model.getJointId("forearm_joint")
        rows = []
        for q in cycle.q[::SAMPLE_STRIDE]:
            pin.framesForwardKinematics(model, data, device.to_pinocchio(q))
            rows.append((data.oMf[frame].copy(), data.oMi[forearm].rotation.copy()))
        placements[name] = rows
    for (old, forearm_axes), (new, _) in zip(placements["old"], placements["new"], strict=True):
        np.testing.assert_allclose(
            new.translation - old.translation, shift * forearm_axes[:, 1], rtol=0, atol=FK_ATOL
        )
        np.testing.assert_allclose(new.rotation, old.rotation, rtol=0, atol=FK_ATOL)
