"""Drives: cylinder chamber pressures and the rack force, against hand values and the defining
balances; impossible drive sizes are refused by the parameters."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.loop import check_device
from feeder.device.parameters import FeederParameters
from feeder.dynamics.drives import cylinder_pressures, piston_areas, rack_force
from feeder.exceptions import InputError

from ..dynamics.cases import device

BALANCE = 1e-14
"""Relative: pressure × area and force / radius are single floating-point operations."""

HAND_DIGITS = 2e-4
"""Relative: the hand values below are rounded to 4 significant digits (78.54 cm², 50.27 cm²),
at most 1e-4 off; a wrong area (radius for diameter, bore for annulus) is off by ≥ 30%."""

BAR = 1e5
"""[Pa] One bar; 1 bar on 1 cm² pushes 10 N."""


def _cylinder(bore: float, rod: float) -> FeederParameters:
    """The reference device with another lift cylinder, checked like any parameter set."""
    params = replace(PROJECTILE_FEEDER, bore_diameter=bore, rod_diameter=rod)
    params.check()
    return params


def test_round_cylinder_against_hand_values():
    """A 100/60 mm cylinder: the bore is π · 5² = 78.54 cm² and the annulus π (5² − 3²) =
    50.27 cm², so 100 bar push 78.54 kN on the cap side and pull 50.27 kN on the rod side."""
    p = _cylinder(0.100, 0.060)
    pressures = cylinder_pressures(p, np.array([78_540.0, -50_270.0]))
    assert pressures.cap[0] == pytest.approx(100.0 * BAR, rel=HAND_DIGITS)
    assert pressures.rod[1] == pytest.approx(100.0 * BAR, rel=HAND_DIGITS)
    assert pressures.rod[0] == 0.0 and pressures.cap[1] == 0.0


def test_annulus_of_a_3_4_5_cylinder_is_a_40_mm_bore():
    """Bore 50 mm, rod 30 mm: D² − d² = 40², so its annulus is exactly the bore of a 40 mm
    cylinder (no π involved), and pulling needs (50/40)² = 25/16 of the pushing pressure."""
    force = np.array([-1234.5, 1234.5])
    pressures = cylinder_pressures(_cylinder(0.050, 0.030), force)
    pull, push = pressures.rod[0], pressures.cap[1]
    forty = cylinder_pressures(_cylinder(0.040, 0.020), -force)
    assert pull == pytest.approx(forty.cap[0], rel=BALANCE)
    assert pull / push == pytest.approx(25.0 / 16.0, rel=BALANCE)


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


def test_drive_power_is_the_actuator_power_along_a_cycle(result):
    """Hydraulic power (p_cap A_cap − p_rod A_rod) ṙ2 = F ṙ2 and rack power F_rack r φ̇4 = M φ̇4
    at every sample: the cycle's drives come from its own loads, with their signs."""
    kin, loads, params = result.kinematics, result.loads, device().params
    cap, annulus = piston_areas(params)
    dr2, dphi4 = kin.v[:, 1], kin.v[:, 3]
    hydraulic = (result.pressures.cap * cap - result.pressures.rod * annulus) * dr2
    mechanical = loads.piston_force * dr2
    scale = np.abs(mechanical).max()
    assert scale > 0.0
    assert np.abs(hydraulic - mechanical).max() <= BALANCE * scale
    rack = result.rack_force * params.pinion_radius * dphi4
    moment = loads.forearm_torque * dphi4
    assert np.abs(rack - moment).max() <= BALANCE * np.abs(moment).max()


@pytest.mark.parametrize(
    ("bore", "rod", "message"),
    [
        (0.05, 0.05, "rod diameter 0.05 m must be smaller than the bore diameter 0.05 m"),
        (0.05, 0.06, "rod diameter 0.06 m must be smaller than the bore diameter 0.05 m"),
        (0.05, 0.0, "rod_diameter must be positive, got 0.0 m"),
        (0.0, 0.0, "bore_diameter must be positive, got 0.0 m"),
        (-0.05, 0.02, "bore_diameter must be positive, got -0.05 m"),
    ],
)
def test_impossible_cylinder_is_refused(bore, rod, message):
    """The drives trust their parameters: the parameter check refuses 0 < rod < bore broken."""
    params = replace(PROJECTILE_FEEDER, bore_diameter=bore, rod_diameter=rod)
    with pytest.raises(InputError, match=message):
        params.check()
    with pytest.raises(InputError, match=message):
        check_device(params)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"pinion_radius": 0.0}, "pinion_radius must be positive"),
        ({"pinion_radius": -0.04}, "pinion_radius must be positive"),
        ({"pinion_radius": float("nan")}, "pinion_radius must be finite"),
        ({"bore_diameter": float("inf")}, "bore_diameter must be finite"),
    ],
)
def test_bad_drive_sizes_are_refused(change, message):
    with pytest.raises(InputError, match=message):
        check_device(replace(PROJECTILE_FEEDER, **change))
