"""The device: frames by name, the paper's coordinates by joint name, and parameter sets or
names the loader refuses before building a model."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.feeder import PAPER_JOINTS, load_feeder
from feeder.device.parameters import LinkInertia
from feeder.exceptions import InertiaError, InputError, UnreachablePoseError


def test_frame_ids_by_name(feeder):
    for name in ("piston_pin", "arm_pin", "projectile"):
        assert feeder.model.frames[feeder.frame_id(name)].name == name
    with pytest.raises(InputError, match="no frame 'nope' .* frames: .*'arm_pin'"):
        feeder.frame_id("nope")


def test_paper_order_is_mapped_by_joint_name(feeder):
    """to_pinocchio puts φ1, r2, φ3, φ4 at their joints' positions; to_paper undoes it."""
    model = feeder.model
    paper = np.array([2.1, 0.3, 0.7, 0.4])
    q = feeder.to_pinocchio(paper)
    for value, joint in zip(paper, PAPER_JOINTS, strict=True):
        assert q[model.joints[model.getJointId(joint)].idx_q] == value
    np.testing.assert_array_equal(feeder.to_paper(q), paper)
    batch = np.stack([paper, paper[::-1]])
    np.testing.assert_array_equal(feeder.to_paper(feeder.to_pinocchio(batch)), batch)


@pytest.mark.parametrize(
    "changes, error, message",
    [
        ({"d3": 0.0}, InputError, "d3 must be positive, got 0.0"),
        ({"swing": 10.0}, InputError, "swing 572.958°"),
        ({"r2_max": 0.4}, UnreachablePoseError, r"r2 = 0\.\d+ m, outside the stroke"),
        ({"c": "0.05"}, InputError, "c must be numeric"),
        (
            {"arm": LinkInertia(18.663, (0.238e-2, 5.036e-2, 0.278e-2), "printed")},
            InertiaError,
            "link 'arm'.*triangle",
        ),
    ],
)
def test_load_feeder_checks_the_parameters(changes, error, message):
    with pytest.raises(error, match=message):
        load_feeder(dataclasses.replace(PROJECTILE_FEEDER, **changes))


@pytest.mark.parametrize("name", ["gun", "", "Projectile"])
def test_unknown_device_name(name):
    with pytest.raises(InputError, match=f"unknown device {name!r}"):
        load_feeder(name)


@pytest.mark.parametrize("device", [["projectile"], 1, None, b"projectile"])
def test_a_device_that_is_neither_a_name_nor_parameters_is_refused(device):
    """A list is not hashable: the loader must refuse it before looking it up."""
    with pytest.raises(InputError, match="unknown device"):
        load_feeder(device)
