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


def test_a_pose_file_value_with_a_unit_is_named(tmp_path):
    """'40deg' is not read as NaN and then refused as "not finite": the message shows the text."""
    from feeder.chain.readers import read_pose

    model = load_closed_chain(REPO / "examples" / "four_bar" / "four_bar.urdf", []).model
    (tmp_path / "pose.csv").write_text("joint,value\ncrank_joint,40deg\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"row 2: the value of 'crank_joint' .* got '40deg'$"):
        read_pose(tmp_path / "pose.csv", model)
