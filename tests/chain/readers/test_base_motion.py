"""The base's motion from files: the ``[base]`` table of a mechanism file, hull tables and the
command line's profiles, and their refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import read_spec
from feeder.chain.model.profiles import Bump, Recoil, Slope, Terrain
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
        (
            "t,roll,v_roll\n0,0,0\n1,0.15,0\n2,0.3,0\n",
            r"column 'v_roll' contradicts 'roll' between t = 0 s and 1 s .* says 0 \(off by 0.15,",
        ),
        (
            "t,roll_deg,v_roll_deg\n0,0,0\n1,5,0\n2,10,0\n",
            r"column 'v_roll_deg' contradicts 'roll_deg' .* changes by 5 per second there",
        ),
        (
            "t,roll_deg,v_roll\n0,0,0\n1,5,0\n2,10,0\n",
            r"'v_roll' contradicts 'roll_deg' .* says 0 in the unit of 'roll_deg'",
        ),
        (
            "t,z,v_z,a_z\n0,0,0,0\n1,1,2,0\n2,4,4,0\n",
            r"column 'a_z' contradicts 'v_z' between t = 0 s and 1 s",
        ),
        (
            "t,z,a_z\n0,0,0\n1,1.5,0\n2,6,0\n",
            r"column 'a_z' contradicts 'z' between t = 0 s and 2 s .* per second²",
        ),
    ],
    ids=["zero-roll-rate", "in-degrees", "mixed-units", "acceleration", "acceleration-of-z"],
)
def test_hull_table_rates_that_contradict_their_values_are_refused(tmp_path, text, match):
    """Rates given beside their values are checked as a motion table's are: all-zero rates
    beside a moving roll column are refused, in the unit each column is written in."""
    path = tmp_path / "hull.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match):
        read_hull_table(path)


def test_hull_table_with_consistent_rates_is_accepted(tmp_path):
    """A roll of 0.1 rad/s given in radians, its rate in degrees per second, and a heave
    z = t² with its rate 2t and acceleration 2: accepted, the rates as given."""
    path = tmp_path / "hull.csv"
    path.write_text(
        "t,roll,v_roll_deg,a_roll,z,v_z,a_z\n"
        "0,0,5.7296,0,0,0,2\n1,0.1,5.7296,0,1,2,2\n2,0.2,5.7296,0,4,4,2\n"
    )
    channels = read_hull_table(path).channels(np.array([1.0]))
    np.testing.assert_allclose(channels.rate[0, [2, 3]], [2.0, math.radians(5.7296)])
    np.testing.assert_allclose(channels.acceleration[0, [2, 3]], [2.0, 0.0])


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


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (
            "t,roll\n0,0\n1,30\n2,0\n",
            r"roll = 30 rad \(1719°\) at t = 1 s .* name the column roll_deg",
        ),
        (
            "t,roll_deg\n0,0\n1,1719\n2,0\n",
            r"roll_deg = 30 rad \(1719°\) at t = 1 s is beyond [^;]*$",
        ),
        ("t,pitch\n0,0\n1,0.1\n2,0.2\n", None),
        ("t,z\n0,0\n0.01,0.5\n0.02,0\n", r"a_z \(differentiated\) = -1e\+04 m/s² at t = 0 s"),
        (
            "t,a_x\n0,0\n1,1e12\n",
            r"a_x = 1e\+12 m/s² at t = 1 s is beyond the plausible ±392.4 m/s²",
        ),
    ],
    ids=["roll-in-degrees", "roll-deg-too-steep", "plausible", "differentiated", "acceleration"],
)
def test_hull_table_limits(tmp_path, text, match):
    """A hull table past a plausible limit names the file, the column as given, the value in
    radians and degrees and its time; a radian column that would be plausible in degrees, its
    _deg name. The differentiated z is the parabola through its three rows: z̈ = −2 · 0.5 m /
    (0.01 s)² = −1e4 m/s² at every row."""
    path = tmp_path / "hull.csv"
    path.write_text(text)
    if match is None:
        read_hull_table(path)
        return
    with pytest.raises(InputError, match=f"^hull motion hull.csv: {match}"):
        read_hull_table(path)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("terrain:frequency=1e6", r"^base profile: terrain frequency is 1e\+06 Hz"),
        (
            "recoil:amplitude_deg=1e6",
            r"^base profile: recoil .*: its pitch reaches ±1.745e\+04 rad",
        ),
        ("bump:peak=1e12", r"^base profile: bump: .*: its z acceleration reaches ±1e\+12 m/s²"),
        ("terrain:pitch_deg=1000", r"pitch reaches ±17.45 rad \(1000°\)"),
        ("terrain:roll_phase_deg=400", r"roll_phase is 6.981 rad \(400°\)"),
    ],
)
def test_implausible_profiles_from_the_command_line(text, match):
    with pytest.raises(InputError, match=match):
        parse_profile(text)


def test_base_table_limits(tmp_path):
    """Each alone, and the slope with a ride together, named with the file and [base]."""
    terrain = {"type": "terrain", "pitch_deg": 20.0}
    for table, match in [
        ({"roll_deg": 60.0}, r"^m.toml \[base\]: slope: pitch 0°, roll 60°: its roll reaches"),
        ({"profile": [{"type": "bump", "peak": 1e12}]}, r"^m.toml \[\[base.profile\]\] #1: bump"),
        (
            {"pitch_deg": 30.0, "profile": [terrain]},
            r"^m.toml \[base\]: the base's profiles together \(slope: pitch 30°, roll 0°; "
            r"terrain: .*\): their pitch reaches ±0.8727 rad \(50°\)",
        ),
    ]:
        with pytest.raises(InputError, match=match):
            read_base(table, tmp_path, "m.toml")
    read_base({"pitch_deg": 20.0, "profile": [terrain]}, tmp_path, "m.toml")
