"""The base's motion from files: the ``[base]`` table of a mechanism file, hull tables and the
command line's profiles, and their refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import read_spec
from feeder.chain.model.base import Bump, Recoil, Slope, Terrain
from feeder.chain.readers.base_motion import parse_profile, read_base, read_hull_table
from feeder.exceptions import InputError

from ...conftest import REPO

FOUR_BAR = REPO / "examples" / "four_bar"


def test_base_table_in_a_mechanism_file(tmp_path):
    text = (
        (FOUR_BAR / "closures.toml")
        .read_text()
        .replace('urdf = "four_bar.urdf"', f'urdf = "{FOUR_BAR / "four_bar.urdf"}"')
    )
    (tmp_path / "hull.csv").write_text("t,z,pitch_deg\n0,0,0\n1,0.1,2\n2,0.4,3\n")
    text += (
        '\n[base]\nforward = [1.0, 0.0, 0.0]\nroll_deg = 15.0\ntable = "hull.csv"\n'
        '[[base.profile]]\ntype = "terrain"\nheave = 0.05\npitch_deg = 2.0\n'
        '[[base.profile]]\ntype = "recoil"\nstart = 0.5\n'
    )
    (tmp_path / "m.toml").write_text(text)
    base = read_spec(tmp_path / "m.toml").base
    slope, table, terrain, recoil = base.profiles
    assert slope == Slope(0.0, math.radians(15.0))
    assert terrain == Terrain(heave=0.05, pitch=math.radians(2.0))
    assert recoil == Recoil(start=0.5)
    channels = table.channels(np.array([0.5, 1.0]))
    np.testing.assert_allclose(channels.value[:, 2], [0.05, 0.1])
    np.testing.assert_allclose(channels.value[1, 4], math.radians(2.0))
    # second-order differences of z = 0, 0.1, 0.4: the rate at t = 1 s is (0.4 − 0) / 2
    np.testing.assert_allclose(channels.rate[1, 2], 0.2)
    assert "slope" in base.describe() and "terrain" in base.describe()


def test_hull_table_with_given_rates(tmp_path):
    path = tmp_path / "hull.csv"
    path.write_text("t,x,v_x,a_x,yaw,v_yaw,a_yaw\n0,0,1,2,0,0.1,0\n1,2,3,2,0.1,0.1,0\n")
    channels = read_hull_table(path).channels(np.array([0.5]))
    np.testing.assert_allclose(channels.rate[0, [0, 5]], [2.0, 0.1])
    np.testing.assert_allclose(channels.acceleration[0, [0, 5]], [2.0, 0.0])
    with pytest.raises(InputError, match="covers"):
        read_hull_table(path).channels(np.array([1.5]))


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("t,z,heave\n0,0,0\n1,0,0\n2,0,0\n", "unknown column 'heave'"),
        ("t,roll,roll_deg\n0,0,0\n1,0,0\n2,0,0\n", "both given"),
        ("t,z\n0,0\n1,0\n", "at least 3 rows"),
        ("t,z\n0,0\n0,1\n1,2\n", "increase"),
    ],
)
def test_hull_table_refusals(tmp_path, text, match):
    path = tmp_path / "hull.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match):
        read_hull_table(path)


def test_profiles_from_the_command_line():
    assert parse_profile("bump") == Bump()
    assert parse_profile("terrain:heave=0.1, frequency=2") == Terrain(heave=0.1, frequency=2.0)
    assert parse_profile("recoil:amplitude_deg=3") == Recoil(amplitude=math.radians(3.0))
    for text, match in [
        ("wave", "unknown base profile"),
        ("bump:height=2", "no parameters"),
        ("bump:peak", "key=value"),
        ("bump:peak=big", "number"),
        ("recoil:damping=1.5", "damping"),
        ("terrain:heave=-1", "heave is an amplitude, ≥ 0, got -1"),
        ("terrain:heave=0.1,heave=0.2", "heave is given twice"),
    ]:
        with pytest.raises(InputError, match=match):
            parse_profile(text)


def test_base_table_refusals(tmp_path):
    for table, match in [
        ([], "must be a table"),
        ({"tilt": 1}, "unknown keys"),
        ({"forward": [1, 0]}, "3 numbers"),
        ({"profile": [{"heave": 1}]}, "type"),
        ({"table": 3}, "file name"),
        ({"roll_deg": "steep"}, "numeric"),
    ]:
        with pytest.raises(InputError, match=match):
            read_base(table, tmp_path, "m.toml")
