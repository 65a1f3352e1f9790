"""Fixtures of the forward-run tests."""

from __future__ import annotations

import pytest

from feeder.chain import ChainDynamics

from .delta import DELTA


@pytest.fixture(scope="module")
def delta():
    """The planar delta robot of the CAD exports, at rest at its assembled pose, undriven:
    its dynamics and that pose."""
    from feeder.study.analyze import mount_mechanism

    spec, chain, _, _, q0 = mount_mechanism(DELTA / "robot.yaml", DELTA / "robot.urdf", None)
    return ChainDynamics(chain, spec.actuated), q0
