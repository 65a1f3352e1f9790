"""``[[control]]`` tables of a mechanism file and of a ``--control`` file: read strictly (SI
units, gains two ways, limits, lag or bandwidth, the reference read as a motion table), each
refusal one line naming the table, unknown keys with the nearest known one
(feeder.chain.readers.control)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import read_spec
from feeder.chain.readers.control import read_control_file
from feeder.chain.readers.motion_table import read_motion
from feeder.exceptions import InputError

from ...conftest import REPO, four_bar_file

FOUR_BAR = REPO / "examples" / "four_bar"
REFERENCE = (FOUR_BAR / "motion.csv").as_posix()


def write(tmp_path, control: str):
    return four_bar_file(tmp_path, control)


def test_a_control_table_is_read_with_its_reference(tmp_path):
    path = write(
        tmp_path,
        f'[[control]]\njoint = "crank_joint"\nreference = "{REFERENCE}"\nkp = 400.0\nkd = 40\n'
        "force_limit = 2.5\nlag = 0.01\nrate_limit = 1e3\n",
    )
    (spec,) = read_spec(path).control
    table = read_motion(FOUR_BAR / "motion.csv", ("crank_joint",))
    assert spec.joint == "crank_joint" and spec.reference == FOUR_BAR / "motion.csv"
    np.testing.assert_array_equal(spec.t, table.t)
    np.testing.assert_array_equal(np.column_stack([spec.q, spec.v, spec.a]),
                                  np.column_stack([table.x, table.dx, table.ddx]))  # fmt: skip
    assert (spec.kp, spec.kd, spec.force_limit) == (400.0, 40.0, (-2.5, 2.5))
    assert (spec.lag, spec.rate_limit, spec.area) == (0.01, 1e3, None)


def test_an_element_s_push_may_drive_the_joint(tmp_path):
    """``element`` names the force element whose push drives the joint (checked against the
    mechanism by the controller, feeder.chain.dynamics.control); without it, None."""
    path = write(
        tmp_path,
        f'[[control]]\njoint = "crank_joint"\nelement = "lift"\nreference = "{REFERENCE}"\n'
        "omega = 10.0\nforce_limit = 300.0\n",
    )
    (spec,) = read_spec(path).control
    assert (spec.joint, spec.element, spec.force_limit) == ("crank_joint", "lift", (-300, 300))
    (spec,) = read_spec(write(tmp_path, "[[control]]\n" + BASE + "omega = 1\n")).control
    assert spec.element is None


def test_the_gains_from_the_natural_frequency_and_the_lag_from_the_bandwidth(tmp_path):
    """K_p = ω², K_d = 2ζω (ζ default 1); T = 1 / (2π f); a reference relative to the file;
    an asymmetric force limit."""
    (tmp_path / "ref.csv").write_text("t,q_crank_joint\n0,0\n0.5,0.5\n1,1\n", encoding="utf-8")
    path = write(
        tmp_path,
        '[[control]]\njoint = "crank_joint"\nreference = "ref.csv"\nomega = 20.0\n'
        "bandwidth = 5.0\nforce_limit = [-1.0, 3.0]\n",
    )
    (spec,) = read_spec(path).control
    assert spec.reference == tmp_path / "ref.csv"
    assert (spec.kp, spec.kd) == (400.0, 40.0)
    assert spec.lag == pytest.approx(1.0 / (2.0 * math.pi * 5.0), rel=1e-15)
    assert spec.force_limit == (-1.0, 3.0) and spec.rate_limit == math.inf
    path = write(tmp_path, '[[control]]\njoint = "crank_joint"\nreference = "ref.csv"\n'
                 "omega = 20.0\nzeta = 0.5\n")  # fmt: skip
    (spec,) = read_spec(path).control
    assert (spec.kp, spec.kd) == (400.0, 20.0)


def test_two_joints_share_one_reference_read_once(tmp_path):
    (tmp_path / "ref.csv").write_text("t,q_a,q_b\n0,0,1\n0.5,0.5,2\n1,1,3\n", encoding="utf-8")
    (tmp_path / "control.toml").write_text(
        '[[control]]\njoint = "b"\nreference = "ref.csv"\nkp = 1\nkd = 1\n\n'
        '[[control]]\njoint = "a"\nreference = "ref.csv"\nkp = 2\nkd = 2\n',
        encoding="utf-8",
    )
    b, a = read_control_file(tmp_path / "control.toml")
    assert (b.joint, a.joint) == ("b", "a")  # in the file's order
    np.testing.assert_array_equal(b.q, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(a.q, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(a.v, 1.0, rtol=1e-14)  # differentiated from the positions


BASE = f'joint = "crank_joint"\nreference = "{REFERENCE}"\n'


@pytest.mark.parametrize(
    ("table", "message"),
    [
        (BASE + "kpp = 1\nkd = 1\n", r"unknown keys \['kpp'\]; did you mean 'kp'\?"),
        (f'reference = "{REFERENCE}"\nkp = 1\nkd = 1\n', 'joint = "…" is required'),
        ('joint = "crank_joint"\nkp = 1\nkd = 1\n', "reference = .* is required"),
        (BASE, "the gains are required"),
        (BASE + "kp = 1\n", "the gains are required"),
        (BASE + "kp = 1\nkd = 1\nomega = 2\n", "not both"),
        (BASE + "zeta = 1\n", "zeta needs omega"),
        (BASE + "kp = -1\nkd = 1\n", r"kp must be > 0 \[1/s²\]"),
        (BASE + "kp = 1\nkd = -1\n", r"kd must be ≥ 0 \[1/s\]"),
        (BASE + 'kp = "1"\nkd = 1\n', "must be numeric, got the text"),
        (BASE + "kp = 1\nkd = 1\nforce_limit = [3, 1]\n", "low < high"),
        (BASE + "kp = 1\nkd = 1\nforce_limit = 0\n", "force_limit must be > 0"),
        (BASE + "kp = 1\nkd = 1\nrate_limit = 10\n", "give lag .* or bandwidth"),
        (BASE + "kp = 1\nkd = 1\nlag = 0.1\nbandwidth = 2\n", "lag .* or bandwidth .*not both"),
        (BASE + "kp = 1\nkd = 1\narea = 0\n", r"area must be > 0 \[m²\]"),
        (BASE + "kp = 1\nkd = 1\n\n[[control]]\n" + BASE + "kp = 1\nkd = 1\n", "twice"),
        (BASE + 'kp = 1\nkd = 1\nelement = ""\n', "names a spring or cylinder"),
        (BASE + "kp = 1\nkd = 1\nelement = 3\n", "names a spring or cylinder"),
        (BASE + 'kp = 1\nkd = 1\nelement = "c"\narea = 1e-3\n', "area is for a joint driven"),
        (
            BASE + 'kp = 1\nkd = 1\nelement = "c"\n\n[[control]]\njoint = "rocker_joint"\n'
            f'reference = "{REFERENCE}"\nkp = 1\nkd = 1\nelement = "c"\n',
            "element 'c' drives two joints",
        ),  # fmt: skip
        ('joint = "crank_joint"\nreference = "nowhere.csv"\nkp = 1\nkd = 1\n', "not found"),
    ],
)
def test_bad_control_tables_are_refused_in_one_line(tmp_path, table, message):
    path = write(tmp_path, "[[control]]\n" + table)
    with pytest.raises(InputError, match=message) as error:
        read_spec(path)
    assert "\n" not in str(error.value)
    assert "[[control]] #" in str(error.value) or "not found" in str(error.value)


def test_a_control_file_holds_control_tables_only(tmp_path):
    path = tmp_path / "control.toml"
    path.write_text('[[controls]]\njoint = "a"\n', encoding="utf-8")
    with pytest.raises(InputError, match=r"only \[\[control\]\] .* did you mean 'control'\?"):
        read_control_file(path)
    path.write_text("", encoding="utf-8")
    with pytest.raises(InputError, match=r"no \[\[control\]\] table"):
        read_control_file(path)
    with pytest.raises(InputError, match="control file not found"):
        read_control_file(tmp_path / "missing.toml")
    with pytest.raises(InputError, match="control file .* is a folder, not a file"):
        read_control_file(tmp_path)


def test_a_bad_reference_names_the_tables_that_read_it(tmp_path):
    (tmp_path / "ref.csv").write_text("t,q_a,q_other\n0,0,1\n0.5,0.5,2\n1,1,3\n")
    (tmp_path / "control.toml").write_text(
        '[[control]]\njoint = "a"\nreference = "ref.csv"\nkp = 1\nkd = 1\n', encoding="utf-8"
    )
    with pytest.raises(InputError, match=r"\[\[control\]\] of \['a'\]: .*'q_other'"):
        read_control_file(tmp_path / "control.toml")
