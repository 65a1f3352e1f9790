"""Every public reader of :mod:`feeder.chain.readers` refuses an argument of the wrong type
(None, a number) with the package's :class:`~feeder.exceptions.InputError`, before it opens a
file: never a bare TypeError or AttributeError from inside."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import feeder
from feeder.chain import load_closed_chain, load_mechanism, read_spec
from feeder.chain.readers import (
    build_model,
    check_inertia,
    check_urdf,
    mesh_path,
    read_force_file,
    read_motion,
    read_pose,
    read_table,
    read_urdf,
)
from feeder.chain.readers.extended_urdf import read_extended_urdf
from feeder.chain.readers.mjcf import check_mjcf, read_mjcf
from feeder.chain.readers.sdf import load_sdf, read_sdf
from feeder.chain.readers.side_file import read_toml
from feeder.exceptions import InputError

from ...conftest import REPO

EXAMPLE = REPO / "examples" / "four_bar"
MODEL = pin.buildSampleModelManipulator()

READERS = {
    "feeder.chain.load_closed_chain": lambda bad: feeder.chain.load_closed_chain(bad, []),
    "load_closed_chain": lambda bad: load_closed_chain(bad, []),
    "read_spec": lambda bad: read_spec(bad),
    "read_spec(model=)": lambda bad: read_spec(
        EXAMPLE / "closures.toml", 3 if bad is None else bad
    ),
    "read_toml": lambda bad: read_toml(bad),
    "read_extended_urdf": lambda bad: read_extended_urdf(bad),
    "load_mechanism": lambda bad: load_mechanism(bad),
    "read_urdf": lambda bad: read_urdf(bad),
    "check_urdf": lambda bad: check_urdf(bad),
    "build_model": lambda bad: build_model(bad),
    "read_sdf": lambda bad: read_sdf(bad),
    "load_sdf": lambda bad: load_sdf(bad),
    "check_mjcf": lambda bad: check_mjcf(bad),
    "read_mjcf": lambda bad: read_mjcf(bad),
    "read_motion": lambda bad: read_motion(bad, ("crank_joint",)),
    "read_motion(independent=)": lambda bad: read_motion(EXAMPLE / "motion.csv", bad),
    "read_pose": lambda bad: read_pose(bad, MODEL),
    "read_pose(model=)": lambda bad: read_pose(EXAMPLE / "motion.csv", bad),
    "read_force_file": lambda bad: read_force_file(bad),
    "read_table": lambda bad: read_table(bad, ("force",)),
    "mesh_path": lambda bad: mesh_path(bad, EXAMPLE / "four_bar.urdf"),
    "mesh_path(urdf=)": lambda bad: mesh_path("link.stl", bad),
    "check_inertia(mass=)": lambda bad: check_inertia(
        "link", bad if bad is None else str(bad), np.eye(3)
    ),
    "check_inertia(inertia=)": lambda bad: check_inertia("link", 1.0, bad),
}
"""Each reader with the argument under test replaced (the others valid). ``read_spec``'s
``model=None`` means "the file's own model", so it gets a number; ``check_inertia``'s mass a
text instead of a number (a number is a mass)."""


@pytest.mark.parametrize("bad", [None, 3], ids=["None", "int"])
@pytest.mark.parametrize("call", READERS.values(), ids=READERS.keys())
def test_a_wrong_type_is_an_input_error_on_one_line(call, bad):
    with pytest.raises(InputError) as caught:
        call(bad)
    assert "\n" not in str(caught.value)
