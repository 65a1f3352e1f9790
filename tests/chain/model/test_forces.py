"""Force elements as data: their checks, tables and laws."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain.model.forces import Cylinder, JointSpring, Load, Spring, Table, read_table
from feeder.exceptions import InputError


def test_a_table_interpolates_and_refuses_to_extrapolate(tmp_path):
    path = tmp_path / "push.csv"
    path.write_text("t,force\n0,0\n1,10\n3,-10\n")
    table = read_table(path, ("force",))
    assert table(0.5)[0] == pytest.approx(5.0) and table(2.0)[0] == pytest.approx(0.0)
    table.check_covers(0.0, 3.0)
    with pytest.raises(InputError, match="push.csv covers t = 0…3 s"):
        table.check_covers(0.0, 3.5)
    for text, message in (
        ("time,force\n0,0\n1,1\n", "header"),
        ("t,force\n0,0\n0,1\n", "increasing"),
        ("t,force\n0,0\n1,x\n", "x"),
        ("t,force\n0,nan\n1,1\n", "finite"),
        ("t,force\n0,0\n", "at least two"),
    ):
        path.write_text(text)
        with pytest.raises(InputError, match=message):
            read_table(path, ("force",))
    with pytest.raises(InputError, match="not readable"):
        read_table(tmp_path / "missing.csv", ("force",))


def test_a_cylinder_turns_pressure_into_push_and_back():
    cylinder = Cylinder(("cap", "rod"), bore=0.08, rod=0.045, pressure=12e6, rod_pressure=1e6)
    cap, annulus = math.pi * 0.08**2 / 4.0, math.pi * (0.08**2 - 0.045**2) / 4.0
    assert cylinder.push(0.0) == pytest.approx(12e6 * cap - 1e6 * annulus, rel=1e-15)
    assert cylinder.pressure_for(cylinder.push(0.0) + 1e6 * annulus) == pytest.approx(12e6)
    with pytest.raises(InputError, match="rod < bore"):
        Cylinder(("cap", "rod"), bore=0.05, rod=0.05)


def test_a_joint_spring_resists_with_its_preload():
    spring = JointSpring("hinge", stiffness=2.0, rest=0.5, damping=0.1, preload=0.3)
    assert spring.resistance(0.5, 0.0) == pytest.approx(0.3)
    assert spring.resistance(1.0, 2.0) == pytest.approx(0.3 + 1.0 + 0.2)
    # its energy's derivative is the elastic part of the resistance
    h = 1e-6
    slope = (spring.energy(0.8 + h) - spring.energy(0.8 - h)) / (2 * h)
    assert slope == pytest.approx(spring.resistance(0.8, 0.0), rel=1e-9)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: Spring(("a", "a")), "two distinct frame names"),
        (lambda: Spring(("a", "b"), stiffness=-1.0), "stiffness must be ≥ 0"),
        (lambda: Spring(("a", "b"), force="ten"), "numeric"),
        (lambda: Spring(("a", "b"), rest_length=math.nan), "finite"),
        (lambda: JointSpring(""), "joint name"),
        (lambda: Load("f", force=(1.0, 2.0)), "3 numbers"),
        (lambda: Load("f", force=(1.0, 0, 0), table=Table(np.arange(2.0), np.zeros((2, 6)))),
         "not both"),
        (lambda: Load("f", table=Table(np.arange(2.0), np.zeros((2, 3)))), "six columns"),
    ],
)  # fmt: skip
def test_bad_elements_are_refused(make, message):
    with pytest.raises(InputError, match=message):
        make()
