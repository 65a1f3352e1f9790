"""A user's mechanism from files: the closure side-file, the motion table and an MJCF model."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain.assembly.partition import Partition
from feeder.chain.mobility import mobility
from feeder.chain.readers.mechanism import load_mechanism, read_spec
from feeder.chain.readers.motion_table import read_motion
from feeder.chain.readers.spec import SIDE_FILE_MAX_BYTES, SIDE_FILE_MAX_DEPTH
from feeder.exceptions import InputError, UrdfError

from ...conftest import REPO

EXAMPLE = REPO / "examples" / "four_bar"

MJCF_FOUR_BAR = """<mujoco model="four_bar">
  <worldbody>
    <body name="ground">
      <body name="crank">
        <joint name="crank_joint" type="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.04 0 0" size="0.005" mass="0.1"/>
        <body name="coupler" pos="0.04 0 0">
          <joint name="coupler_joint" type="hinge" axis="0 0 1"/>
          <geom type="capsule" fromto="0 0 0 0.12 0 0" size="0.005" mass="0.2"/>
        </body>
      </body>
      <body name="rocker" pos="0.1 0 0">
        <joint name="rocker_joint" type="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.08 0 0" size="0.005" mass="0.15"/>
      </body>
    </body>
  </worldbody>
  <equality>
    <connect name="pin" body1="coupler" body2="rocker" anchor="0.12 0 0"/>
  </equality>
</mujoco>
"""
"""The example four-bar in MJCF, its loop closed by an ``equality/connect`` (the parser reads
only the first body under ``worldbody``, hence the jointless ``ground``)."""


def test_example_side_file(tmp_path):
    spec = read_spec(EXAMPLE / "closures.toml")
    assert spec.model == EXAMPLE / "four_bar.urdf" and spec.model_format == "urdf"
    assert spec.actuated == spec.independent == ("crank_joint",)
    np.testing.assert_array_equal(spec.gravity, [0.0, -9.81, 0.0])
    (closure,) = spec.closures
    assert (closure.frame_a, closure.frame_b, closure.kind) == (
        "coupler_tip",
        "rocker_tip",
        "revolute",
    )
    chain = load_mechanism(spec)
    np.testing.assert_array_equal(chain.model.gravity.linear, [0.0, -9.81, 0.0])


def test_mjcf_connect_becomes_a_point_closure(tmp_path):
    path = tmp_path / "four_bar.xml"
    path.write_text(MJCF_FOUR_BAR)
    side = tmp_path / "closures.toml"
    joints = 'actuated = ["crank_joint"]\nindependent = ["crank_joint"]\n'
    side.write_text(f'[mechanism]\nmjcf = "four_bar.xml"\n{joints}')
    chain = load_mechanism(read_spec(side))
    (closure,) = chain.closures
    assert closure.kind == "point" and closure.label == "pin"
    q = Partition(chain, ["crank_joint"]).assemble(np.array([math.radians(40.0), -0.35, 1.0]))
    report = mobility(chain, q, ["crank_joint"])
    assert (report.rank, report.mobility) == (2, 1)
    # MuJoCo's connect: the anchor is the coupler's tip (0.12 m along it); on the rocker it is
    # where that tip is at qpos0 (all joints 0: at x = 0.04 + 0.12), 0.06 m from its pivot.
    pin_position = chain.data.oMf[chain.frame_ids[0][0]].translation
    rocker = chain.data.oMi[chain.model.getJointId("rocker_joint")].translation
    assert abs(np.linalg.norm(pin_position - rocker) - 0.06) <= 1e-12


MECHANISM = '[mechanism]\nurdf = "x.urdf"\nactuated = ["a"]\nindependent = ["a"]\n'
"""A valid [mechanism] table that the bad cases below extend."""


@pytest.mark.parametrize(
    "text, message",
    [
        ("not toml [", "not a readable TOML"),
        ('[mechanism]\nactuated = ["a"]\nindependent = ["a"]\n', "name the model"),
        (MECHANISM.replace('["a"]', '"a"', 1), "'actuated' must be a list of distinct"),
        (MECHANISM + "rates = 3\n", r"rates must be a table \{joint = rate"),
        (MECHANISM + 'rates = {a = "fast"}\n', r"rates\.a \[rad/s or m/s\] must be"),
        (MECHANISM + "rates = {a = nan}\n", r"rates\.a \[rad/s or m/s\]"),
        (MECHANISM + "rates = {a = true}\n", "truth value"),
        (MECHANISM + "speed = 3\n", "unknown keys"),
        (MECHANISM + "gravity = [0, 1]\n", "3 numbers"),
        (MECHANISM + '[[closure]]\nframes = ["a"]\n', "two frame names"),
        (MECHANISM + '[[closure]]\nframes = ["a", "b"]\ntype = "ball"\n', "'type' must be one of"),
        ("[other]\n", "unknown sections"),
        (MECHANISM.replace('independent = ["a"]', "independent = []"), "non-empty"),
        (
            MECHANISM + '[[closure]]\nframes = ["a", "b"]\ntype = "revolute"\naxis = 5\n',
            "'axis' must be 3 numbers",
        ),
        (
            MECHANISM + '[[closure]]\nframes = ["a", "b"]\n',
            r"\[\[closure\]\] #1: 'type' is required: one of \['point', 'revolute', 'weld'\]",
        ),
    ],
    ids=[
        "syntax",
        "no-model",
        "actuated",
        "rates-table",
        "rates-text",
        "rates-nan",
        "rates-bool",
        "unknown-key",
        "gravity",
        "frames",
        "type",
        "section",
        "no-independent",
        "axis",
        "no-type",
    ],
)
def test_side_file_errors_name_the_key(tmp_path, text, message):
    path = tmp_path / "closures.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=message) as info:
        read_spec(path)
    assert "\n" not in str(info.value)


def test_rates_are_read_and_actuated_may_be_empty(tmp_path):
    """A passive mechanism (no actuated joint) with initial rates: each rate a number, where it
    was read kept for the messages."""
    path = tmp_path / "closures.toml"
    path.write_text(
        MECHANISM.replace('actuated = ["a"]', "actuated = []") + "rates = {a = 1.5, b = -2}\n"
    )
    spec = read_spec(path)
    assert spec.actuated == ()
    assert [(name, value) for name, value, _ in spec.rates] == [("a", 1.5), ("b", -2.0)]
    assert spec.rates[0][2].endswith("[mechanism] rates")


@pytest.mark.parametrize("depth", [SIDE_FILE_MAX_DEPTH - 2, 5000])
def test_deep_nesting_is_refused(tmp_path, depth):
    """Arrays nested one level past the limit ([mechanism] is level 2, its pose 3), or 5000 levels
    (tomllib's recursion ran out of stack there): one line naming the file and the limit."""
    path = tmp_path / "closures.toml"
    path.write_text(MECHANISM + f"pose = {{a = {'[' * depth}{']' * depth}}}\n")
    with pytest.raises(InputError) as info:
        read_spec(path)
    assert str(info.value) == (
        f"{path}: values nested deeper than {SIDE_FILE_MAX_DEPTH} levels, the limit of a "
        "side-file (its lists of names nest 4 levels)"
    )


def test_a_side_file_larger_than_the_limit_is_refused(tmp_path):
    path = tmp_path / "closures.toml"
    path.write_text(MECHANISM + "#" * SIDE_FILE_MAX_BYTES + "\n")
    with pytest.raises(InputError, match=f"larger than {SIDE_FILE_MAX_BYTES} bytes"):
        read_spec(path)


@pytest.mark.parametrize("frames", [("b", "a"), ("a", "b")], ids=["reversed", "repeated"])
def test_a_loop_listed_twice_is_refused(tmp_path, frames):
    """Two [[closure]] tables joining the same frames, in either order, are not two cuts."""
    closure = '[[closure]]\nframes = ["{}", "{}"]\ntype = "point"\n'
    path = tmp_path / "closures.toml"
    path.write_text(MECHANISM + closure.format("a", "b") + closure.format(*frames))
    with pytest.raises(InputError, match=r"\[\[closure\]\] #1 and #2 both join 'a' and 'b'"):
        read_spec(path)


def test_missing_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_spec(tmp_path / "missing.toml")
    side = tmp_path / "closures.toml"
    side.write_text('[mechanism]\nurdf = "missing.urdf"\nactuated = ["a"]\nindependent = ["a"]\n')
    with pytest.raises(UrdfError, match="not found"):
        load_mechanism(read_spec(side))
    with pytest.raises(InputError, match="not found"):
        read_motion(tmp_path / "missing.csv", ("crank_joint",))


def test_motion_table_and_its_derivatives(tmp_path):
    table = read_motion(EXAMPLE / "motion.csv", ("crank_joint",))
    assert table.differentiated == ()
    np.testing.assert_array_equal(table.dx, 2.0 * math.pi)
    path = tmp_path / "positions.csv"
    t = np.linspace(0.0, 1.0, 201)
    rows = "\n".join(f"{float(x)!r},{math.sin(x)!r}" for x in t)
    path.write_text(f"t,q_crank_joint\n{rows}\n")
    table = read_motion(path, ("crank_joint",))
    assert table.differentiated == ("crank_joint",)
    # Second-order differences of sin: error ~ h²/6 |sin'''| with h = 5 ms: 4e-6 (edges 2× more).
    np.testing.assert_allclose(table.dx[:, 0], np.cos(t), rtol=0, atol=1e-5)


@pytest.mark.parametrize(
    "text, message",
    [
        ("t,q_crank_joint\n0,1\n", "at least two rows"),
        ("t,q_crank_joint\n0,1\n0.1,x\n", "must be numbers"),
        ("t,q_crank_joint\n0,1\n0.1,2,3\n", "values, like the header"),
        ("time,q_crank_joint\n0,1\n0.1,2\n", "no column 't'"),
        ("t,q_other\n0,1\n0.1,2\n", "no column 'q_crank_joint'"),
        ("t,q_crank_joint\n0,1\n0,2\n", "increase"),
        ("t,q_crank_joint\n0,1\n0.1,nan\n", "finite"),
        ("t,q_crank_joint\n0,1\n0.1,2\n", "at least 3 rows"),
        (
            "t,q_crank_joint,v_crank_joint,a_crank_joint,q_rocker_joint\n0,1,0,0,2\n0.1,1,0,0,2\n",
            r"column 'q_rocker_joint' is not t nor q_/v_/a_ of the independent joints "
            r"\['crank_joint'\]: remove it, or make its joint independent",
        ),
        ("t,q_crank_joint,q_crank\n0,1,1\n0.1,2,2\n0.2,3,3\n", "column 'q_crank' is not"),
    ],
    ids=[
        "short",
        "text",
        "ragged",
        "no-t",
        "no-joint",
        "time",
        "nan",
        "few-to-differentiate",
        "dependent-joint",
        "misspelt",
    ],
)
def test_motion_table_errors(tmp_path, text, message):
    path = tmp_path / "motion.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_motion(path, ("crank_joint",))


TWO_ROOTS = MJCF_FOUR_BAR.replace(
    """      <body name="rocker" pos="0.1 0 0">
        <joint name="rocker_joint" type="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.08 0 0" size="0.005" mass="0.15"/>
      </body>
    </body>""",
    """    </body>
    <body name="rocker" pos="0.1 0 0">
      <joint name="rocker_joint" type="hinge" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0.08 0 0" size="0.005" mass="0.15"/>
    </body>""",
)


@pytest.mark.parametrize(
    "text, match",
    [
        (TWO_ROOTS, "holds 2 bodies .ground, rocker."),  # Pinocchio kept only `ground`
        (MJCF_FOUR_BAR.replace("<worldbody>", '<include file="x.xml"/><worldbody>'), "<include>"),
        (
            MJCF_FOUR_BAR.replace("</equality>", '<joint joint1="crank_joint"/></equality>'),
            "<equality><joint>",
        ),
        (MJCF_FOUR_BAR.replace('mass="0.2"', 'mass="-0.2"'), "mass='-0.2'"),
        (MJCF_FOUR_BAR.replace('mass="0.2"', 'mass="nan"'), "mass='nan'"),
        (MJCF_FOUR_BAR.replace('mass="0.2"', 'mass="&m;"'), "malformed"),
        ('<!DOCTYPE m [<!ENTITY m "0.2">]>' + MJCF_FOUR_BAR, "document type"),
    ],
)
def test_mjcf_that_pinocchio_would_misread_is_refused(tmp_path, text, match):
    """Each of these was misread without a word (a negative geom mass gave a crank torque of
    2.6e116 N·m, exit 0; two root bodies once crashed the process)."""
    path = tmp_path / "four_bar.xml"
    path.write_text(text)
    side = tmp_path / "closures.toml"
    side.write_text(
        '[mechanism]\nmjcf = "four_bar.xml"\nactuated = ["crank_joint"]\n'
        'independent = ["crank_joint"]\n'
    )
    with pytest.raises(UrdfError, match=match):
        load_mechanism(read_spec(side))
