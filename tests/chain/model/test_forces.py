"""Force elements as data: their checks, tables and laws."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain.model.forces import Cylinder, JointSpring, Load, Spring, Table
from feeder.exceptions import InputError


def test_a_cylinder_turns_pressures_into_its_push():
    cylinder = Cylinder(("cap", "rod"), bore=0.08, rod=0.045, pressure=12e6, rod_pressure=1e6)
    cap, annulus = math.pi * 0.08**2 / 4.0, math.pi * (0.08**2 - 0.045**2) / 4.0
    assert cylinder.push(0.0) == pytest.approx(12e6 * cap - 1e6 * annulus, rel=1e-15)
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
