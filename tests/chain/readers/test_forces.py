"""The ``[[force]]`` tables of a mechanism file."""

from __future__ import annotations

import pytest

from feeder.chain import read_spec
from feeder.chain.model.forces import Cylinder, JointSpring, Load, Spring, Table
from feeder.chain.readers import read_force_file, read_table
from feeder.exceptions import InputError

from ...conftest import REPO


def test_a_table_interpolates_and_refuses_to_extrapolate(tmp_path):
    path = tmp_path / "push.csv"
    path.write_text("t,force\n0,0\n1,10\n3,-10\n")
    table = read_table(path, ("force",))
    assert table(0.5)[0] == pytest.approx(5.0) and table(2.0)[0] == pytest.approx(0.0)
    table.check_covers(0.0, 3.0)
    with pytest.raises(InputError, match="push.csv covers t = 0…3 s"):
        table.check_covers(0.0, 3.5)
    for text, message in (
        ("time,force\n0,0\n1,1\n", "no column 't'"),
        ("t,push\n0,0\n1,1\n", r"the header must be \['t', 'force'\]"),
        ("t,force\n0,0\n0,1\n", "times must increase"),
        ("t,force\n0,0\n1,x\n", "x"),
        ("t,force\n0,nan\n1,1\n", "finite"),
        ("t,force\n0,0\n", "at least two"),
    ):
        path.write_text(text)
        with pytest.raises(InputError, match=message):
            read_table(path, ("force",))
    with pytest.raises(InputError, match="not found"):
        read_table(tmp_path / "missing.csv", ("force",))


def test_every_type_is_read(tmp_path):
    (tmp_path / "push.csv").write_text("t,force\n0,0\n1,5\n")
    (tmp_path / "load.csv").write_text("t,fx,fy,fz,mx,my,mz\n0,0,0,0,0,0,0\n1,1,0,0,0,0,0.1\n")
    path = tmp_path / "forces.toml"
    path.write_text(
        """
[[force]]
type = "spring"
frames = ["a", "b"]
stiffness = 100.0
rest_length = 0.2
damping = 1.5
force_table = "push.csv"

[[force]]
type = "cylinder"
name = "lift"
frames = ["cap", "rod_end"]
bore = 0.08
rod = 0.045
pressure = 12e6

[[force]]
type = "joint_spring"
joint = "hinge"
stiffness = 2.0
preload = 0.3

[[force]]
type = "load"
frame = "tip"
table = "load.csv"
"""
    )
    spring, cylinder, joint_spring, load = read_force_file(path)
    assert isinstance(spring, Spring) and isinstance(spring.force, Table)
    assert spring.push(0.5) == pytest.approx(2.5)
    assert isinstance(cylinder, Cylinder) and cylinder.name == "lift"
    assert isinstance(joint_spring, JointSpring) and joint_spring.preload == 0.3
    assert isinstance(load, Load) and load.wrench(1.0)[5] == pytest.approx(0.1)


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ('type = "rope"', "'type' must be one of"),
        ('type = "spring"\nframes = ["a", "b"]\nstifness = 1.0', "unknown keys \\['stifness'\\]"),
        ('type = "spring"\nframes = ["a", "b"]\nforce = 1.0\nforce_table = "x.csv"', "not both"),
        ('type = "spring"\nframes = ["a", "b"]\nforce_table = "missing.csv"', "not found"),
        ('type = "cylinder"\nframes = ["a", "b"]\nbore = 0.1', "a cylinder needs 'rod'"),
        ('type = "load"\nframe = "tip"\nforce = [1, 2]', "3 numbers"),
        ('type = "joint_spring"\njoint = "hinge"\nstiffness = "stiff"', "numeric"),
    ],
)
def test_bad_entries_are_named(tmp_path, entry, message):
    path = tmp_path / "forces.toml"
    path.write_text(f"[[force]]\n{entry}\n")
    with pytest.raises(InputError, match=rf"forces.toml \[\[force\]\] #1: .*{message}"):
        read_force_file(path)


@pytest.mark.parametrize(
    ("kind", "keys"),
    [
        ("spring", "'frames'"),
        ("cylinder", "'frames', 'bore', 'rod'"),
        ("joint_spring", "'joint'"),
        ("load", "'frame'"),
    ],
)
def test_each_type_names_every_key_it_needs(tmp_path, kind, keys):
    """A table with only its type: the keys its element has no default for, in their order."""
    path = tmp_path / "forces.toml"
    path.write_text(f'[[force]]\ntype = "{kind}"\n')
    with pytest.raises(InputError, match=rf"forces.toml \[\[force\]\] #1: a {kind} needs {keys}$"):
        read_force_file(path)


def test_a_mechanism_file_carries_its_forces():
    spec = read_spec(REPO / "examples" / "andrews_squeezer" / "squeezer.toml")
    assert [type(element) for element in spec.forces] == [Spring, Load]
    with pytest.raises(InputError, match="only \\[\\[force\\]\\] tables"):
        read_force_file(REPO / "examples" / "andrews_squeezer" / "squeezer.toml")


def test_a_byte_order_mark_is_read_as_nothing(tmp_path):
    """Spreadsheets save UTF-8 with a byte-order mark: the first column is still 't', and a TOML
    file with the mark still parses."""
    (tmp_path / "push.csv").write_text("\ufefft,force\n0,0\n1,5\n", encoding="utf-8")
    assert read_table(tmp_path / "push.csv", ("force",))(0.5)[0] == pytest.approx(2.5)
    (tmp_path / "forces.toml").write_text(
        '\ufeff[[force]]\ntype = "spring"\nframes = ["a", "b"]\nforce_table = "push.csv"\n',
        encoding="utf-8",
    )
    (spring,) = read_force_file(tmp_path / "forces.toml")
    assert spring.frames == ("a", "b")
