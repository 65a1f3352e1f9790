"""Drives: cylinder chamber pressures and the rack force, against their defining balances."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from feeder.exceptions import InputError
from feeder.hydraulics import cylinder_pressures, piston_areas, rack_force
from feeder.parameters import PROJECTILE_FEEDER

BALANCE = 1e-14
"""Relative: pressure × area and force / radius are single floating-point operations."""


def test_areas_are_the_bore_and_the_annulus():
    p = PROJECTILE_FEEDER
    cap, annulus = piston_areas(p)
    assert cap == pytest.approx(math.pi * 0.25 * p.bore_diameter**2, rel=BALANCE)
    assert cap - annulus == pytest.approx(math.pi * 0.25 * p.rod_diameter**2, rel=BALANCE)


def test_pressure_times_area_is_the_piston_force():
    p = PROJECTILE_FEEDER
    cap, annulus = piston_areas(p)
    force = np.array([-2000.0, -1.0, 0.0, 1.0, 3000.0])
    pressures = cylinder_pressures(p, force)
    push, pull = force > 0, force < 0
    assert np.allclose(pressures.cap[push] * cap, force[push], rtol=BALANCE, atol=0)
    assert np.allclose(-pressures.rod[pull] * annulus, force[pull], rtol=BALANCE, atol=0)
    assert np.all(pressures.cap[~push] == 0.0) and np.all(pressures.rod[~pull] == 0.0)
    assert np.all(pressures.peak() == np.maximum(pressures.cap, pressures.rod))
    # Pulling needs more pressure than pushing the same force (smaller area).
    assert cylinder_pressures(p, -force[-1:]).rod[0] > pressures.cap[-1]


def test_rack_force_times_radius_is_the_moment():
    p = PROJECTILE_FEEDER
    torque = np.array([-12.0, 0.0, 30.0])
    assert np.allclose(rack_force(p, torque) * p.pinion_radius, torque, rtol=BALANCE, atol=0)


@pytest.mark.parametrize(
    ("bore", "rod"), [(0.05, 0.05), (0.05, 0.06), (0.05, 0.0), (0.0, 0.0), (-0.05, 0.02)]
)
def test_impossible_cylinder_is_refused(bore, rod):
    p = replace(PROJECTILE_FEEDER, bore_diameter=bore, rod_diameter=rod)
    with pytest.raises(InputError, match="rod diameter"):
        cylinder_pressures(p, np.ones(2))


def test_bad_pinion_and_nan_loads_are_refused():
    with pytest.raises(InputError, match="pinion"):
        rack_force(replace(PROJECTILE_FEEDER, pinion_radius=0.0), np.ones(2))
    with pytest.raises(InputError, match="finite"):
        rack_force(PROJECTILE_FEEDER, np.array([1.0, np.nan]))
    with pytest.raises(InputError, match="finite"):
        cylinder_pressures(PROJECTILE_FEEDER, np.array([np.inf]))
