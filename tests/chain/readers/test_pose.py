"""The reference pose given as values (a mechanism file's ``pose = {joint = value}``)."""

from __future__ import annotations

import pytest

from feeder.chain import load_closed_chain
from feeder.chain.readers.pose import pose_from_values
from feeder.exceptions import InputError

from ...conftest import REPO


@pytest.mark.parametrize("value", [True, "0.5", float("nan")])
def test_a_value_that_is_not_a_number_is_refused(value):
    """A TOML ``true`` was once read as 1 rad (a bool is an int to Python)."""
    model = load_closed_chain(REPO / "examples" / "four_bar" / "four_bar.urdf", []).model
    with pytest.raises(InputError, match="pose"):
        pose_from_values([("crank_joint", value, "pose")], model)
