"""The device: frames by name, and parameter sets the loader refuses before building a model."""

from __future__ import annotations

import dataclasses

import pytest

from feeder import (
    PROJECTILE_FEEDER,
    InertiaError,
    InputError,
    LinkInertia,
    UnreachablePoseError,
    load_feeder,
)


def test_frame_ids_by_name(feeder):
    for name in ("piston_pin", "arm_pin", "projectile"):
        assert feeder.model.frames[feeder.frame_id(name)].name == name
    with pytest.raises(InputError, match="no frame 'nope' .* frames: .*'arm_pin'"):
        feeder.frame_id("nope")


@pytest.mark.parametrize(
    "changes, error, message",
    [
        ({"d3": 0.0}, InputError, "d3 must be positive, got 0.0"),
        ({"swing": 10.0}, InputError, "swing 572.958°"),
        ({"r2_max": 0.4}, UnreachablePoseError, r"r2 = 0\.\d+ m, outside the stroke"),
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


def test_unknown_device_name():
    with pytest.raises(InputError, match="'gun'"):
        load_feeder("gun")
