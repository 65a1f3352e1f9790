"""Fixtures of the paper's cross-check tests: each device, its Pinocchio reference, random
states."""

from __future__ import annotations

import pytest

from . import cases


@pytest.fixture(scope="module", params=cases.DEVICE_NAMES)
def device(request):
    return cases.device(request.param)


@pytest.fixture(scope="module")
def reference(device):
    return cases.pinocchio_reference(device.params.name)


@pytest.fixture(scope="module")
def states(device):
    return cases.random_states(device.params.name)
