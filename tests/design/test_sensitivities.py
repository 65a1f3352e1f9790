"""Sensitivities of the device's peaks (feeder.design.sensitivities): every derivative against
central differences of direct cycle runs at another step, elasticities that have a hand value,
parameters whose stepped runs fail (unavailable, with the reason), and refusals."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from feeder.design import design_sensitivities, evaluations
from feeder.design.sensitivities import Scope
from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.feeder import load_feeder
from feeder.dynamics.cycle import cycle_dynamics
from feeder.exceptions import ElevationError, InputError, SingularPoseError
from feeder.motion.laws import CycleSpec
from feeder.study.peaks import cycle_peaks

SPEC = CycleSpec(rate=100.0)
"""100 Hz: 101 samples a 1 s stage, above the 71 at which a peak's sampling miss stays below
0.1 % (no warning); the derivatives need no finer sampling, and each cycle takes ~15 ms."""

ELEVATIONS = (-4.0, 30.0)
"""The envelope's elevations [deg]: the longest travel, where the rod side pulls, and 30°."""

PARAMETERS = ("d3", "payload.mass", "z5", "pinion_radius", "bore_diameter", "rod_diameter")

ROUND_OFF = 1e-12
"""Relative round-off [-] of a peak computed twice with nearby parameters: the worst measured
on the device (2.4e-13 of the piston guide side force, 6.8 N left from 3.4 kN terms) with a
factor 4."""

HAND = 1e-8
"""[-] Tolerance on an elasticity with a hand value: the round-off of these peaks (≤ 2e-15 of
them, measured) over the half step (3e-6 of the parameter) is ≤ 1e-9 in elasticity units, and
their halving error estimates are ≤ 2e-9; a factor 5 above both."""


@pytest.fixture(scope="module")
def result():
    return design_sensitivities(
        PROJECTILE_FEEDER,
        elevations_deg=ELEVATIONS,
        elevation_deg=30.0,
        parameters=PARAMETERS,
        spec=SPEC,
        workers=1,
        progress=False,
    )


def changed(name: str, value: float):
    """The projectile feeder with one parameter set, written out here (not the code's)."""
    if name == "payload.mass":
        return replace(PROJECTILE_FEEDER, payload=replace(PROJECTILE_FEEDER.payload, mass=value))
    return replace(PROJECTILE_FEEDER, **{name: value})


def direct_peaks(params, elevations) -> dict[str, float]:
    """Each peak's largest-magnitude value over ``elevations`` from direct cycle runs."""
    feeder = load_feeder(params)
    rows = []
    for e in elevations:
        dynamics = cycle_dynamics(feeder, math.radians(e), SPEC, forward=False)
        rows.append({peak.name: peak.value for peak in cycle_peaks(dynamics)})
    return {name: max((row[name] for row in rows), key=abs) for name in rows[0]}


@pytest.mark.parametrize("name, big_step", [("d3", 1e-5), ("payload.mass", 1e-3)])
def test_every_derivative_equals_a_central_difference_of_direct_runs(result, name, big_step):
    """The code differentiates over h/2 ≈ 6e-7 m or 1.3e-4 kg; this test over H = 1e-5 m or
    1e-3 kg (8–17 times larger), with its own truncation estimate |D(2H) − D(H)| (three times
    D(H)'s error for a smooth peak)."""
    value = getattr(PROJECTILE_FEEDER, name.split(".")[0])
    value = value.mass if name == "payload.mass" else value
    for scope in result.scopes:
        runs = {
            k: direct_peaks(changed(name, value + k * big_step), scope.elevations_deg)
            for k in (-2, -1, 1, 2)
        }
        for peak in scope.peaks:
            one = (runs[1][peak.name] - runs[-1][peak.name]) / (2 * big_step)
            two = (runs[2][peak.name] - runs[-2][peak.name]) / (4 * big_step)
            entry = scope.entries[(peak.name, name)]
            assert entry.status == "ok", entry
            size = max(abs(runs[k][peak.name]) for k in runs)
            tolerance = abs(two - one) + entry.estimate.error + 2 * ROUND_OFF * size / big_step
            assert abs(entry.derivative - one) <= tolerance, (scope.name, peak.name, one, entry)
            # Tight enough to see an error of 1e-6 in the elasticity (% per %).
            assert tolerance * abs(value) <= 1e-6 * size, (scope.name, peak.name, tolerance)


def test_elasticities_with_a_hand_value(result):
    """Cap pressure F / (πD²/4): −2 in the bore D (the piston force F does not depend on it);
    rod pressure F / (π(D² − d²)/4): −2D²/(D² − d²) in D and 2d²/(D² − d²) in the rod d; rack
    force τ / r: −1 in the pinion radius r. In stage 3 (φ4 = 0, the arm turning about z) the
    forearm moment about its hinge (the arm's y axis) is z5·m5·(a − g)·x_arm: the forearm's own
    centre of gravity lies in the hinge's plane (z = 0), and the payload's acceleration and
    its y-axis moment of momentum do not depend on z5 or m5; so +1 in the payload mass and in
    z5 for the forearm moment and the rack force."""
    D, d = PROJECTILE_FEEDER.bore_diameter, PROJECTILE_FEEDER.rod_diameter
    hand = {
        ("cylinder_cap_pressure", "bore_diameter"): -2.0,
        ("cylinder_rod_pressure", "bore_diameter"): -2 * D**2 / (D**2 - d**2),
        ("cylinder_rod_pressure", "rod_diameter"): 2 * d**2 / (D**2 - d**2),
        ("rack_force", "pinion_radius"): -1.0,
        ("forearm_torque", "payload.mass"): 1.0,
        ("forearm_torque", "z5"): 1.0,
        ("rack_force", "payload.mass"): 1.0,
        ("rack_force", "z5"): 1.0,
    }
    stage_3 = sum(SPEC.durations[:2])
    checked = 0
    for scope in result.scopes:
        for (peak, parameter), expected in hand.items():
            entry = scope.entries[(peak, parameter)]
            if peak in ("forearm_torque", "rack_force"):
                assert entry.peak.time > stage_3  # the argument's premise
            if entry.peak.value == 0.0:  # the rod side never pulls at 30°: no elasticity
                assert scope.name == "elevation" and math.isnan(entry.elasticity)
                assert entry.derivative == 0.0
                continue
            assert entry.elasticity == pytest.approx(expected, abs=HAND), (scope.name, peak)
            checked += 1
    assert checked == 2 * len(hand) - 2


def test_the_envelope_is_the_largest_peak_over_the_elevations(result):
    envelope = {scope.name: scope for scope in result.scopes}["envelope"]
    at_30 = {scope.name: scope for scope in result.scopes}["elevation"]
    direct = direct_peaks(PROJECTILE_FEEDER, ELEVATIONS)
    for peak in envelope.peaks:
        assert peak.value == direct[peak.name]
        assert abs(peak.value) >= abs(next(p for p in at_30.peaks if p.name == peak.name).value)
    assert {peak.elevation_deg for peak in envelope.peaks} <= set(ELEVATIONS)
    assert all(entry.moved == "" for entry in envelope.entries.values())


def test_a_stepped_set_that_does_not_assemble_is_unavailable_with_its_reason():
    """A 10 % step of d3 puts the loading pose outside the piston's stroke: d3 is unavailable,
    with the loop's reason; the payload mass, stepped as much, is computed."""
    found = design_sensitivities(
        PROJECTILE_FEEDER,
        elevation_deg=30.0,
        parameters=["d3", "payload.mass"],
        spec=SPEC,
        factor=0.1,
        workers=1,
        progress=False,
    )
    (scope,) = found.scopes
    d3 = scope.entries[("piston_force", "d3")]
    assert d3.status == "unavailable" and math.isnan(d3.derivative)
    assert d3.reason.startswith("d3 = 0.209 m:") and "outside the stroke" in d3.reason
    mass = scope.entries[("piston_force", "payload.mass")]
    assert mass.status == "ok" and mass.derivative > 0.0
    assert found.cycles == 1 + 4  # the stepped d3 sets were never run


def test_a_cycle_that_fails_makes_its_parameter_unavailable_not_a_crash(monkeypatch):
    original = evaluations.case_peaks

    def failing(case):
        if case.variant.startswith("L1+"):
            raise SingularPoseError("within 5° of the toggle at t = 3.1 s")
        return original(case)

    monkeypatch.setattr(evaluations, "case_peaks", failing)
    found = design_sensitivities(
        PROJECTILE_FEEDER,
        elevation_deg=30.0,
        parameters=["L1", "L2"],
        spec=SPEC,
        workers=1,
        progress=False,
    )
    (scope,) = found.scopes
    assert {e.status for (_, p), e in scope.entries.items() if p == "L2"} == {"ok"}
    reasons = {e.reason for (_, p), e in scope.entries.items() if p == "L1"}
    assert len(reasons) == 1 and "toggle" in reasons.pop()


def test_workers_give_the_same_derivatives_as_this_process():
    runs = [
        design_sensitivities(
            PROJECTILE_FEEDER,
            elevation_deg=70.0,
            parameters=["L2"],
            spec=SPEC,
            workers=workers,
            progress=False,
        )
        for workers in (1, 2)
    ]
    here, pool = (run.scopes[0].entries for run in runs)
    assert [e.derivative for e in here.values()] == [e.derivative for e in pool.values()]
    assert np.isfinite([e.derivative for e in here.values()]).all()


@pytest.mark.parametrize(
    "arguments, error, message",
    [
        ({"parameters": ["L7"]}, InputError, "parameter 'L7' is not differentiable"),
        ({"parameters": ["swing"]}, InputError, "an angle"),
        ({"parameters": ["payload"]}, InputError, "payload.mass"),
        ({"parameters": ["d3", "d3"]}, InputError, "repeat"),
        ({"elevations_deg": [-4.0, 80.0]}, ElevationError, "80"),
        ({"elevation_deg": -10.0}, ElevationError, "-10"),
        ({"factor": 0.0}, InputError, "relative step"),
        ({"elevations_deg": None, "elevation_deg": None}, InputError, "elevation"),
        ({"elevations_deg": ["x"]}, InputError, r"elevation \[deg\] must be numeric, got the"),
        ({"elevations_deg": [30.0, True]}, InputError, "truth value"),
        ({"elevations_deg": []}, InputError, "at least one elevation"),
    ],
)
def test_bad_input_is_refused_in_one_line(arguments, error, message):
    kwargs = {"elevation_deg": 30.0, "spec": SPEC, "workers": 1, "progress": False}
    with pytest.raises(error, match=message) as info:
        design_sensitivities(PROJECTILE_FEEDER, **(kwargs | arguments))
    assert type(info.value) is error  # not a bare ValueError, nor another subclass
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "name, elevations, title",
    [
        ("elevation", (30.0,), "ε = 30°"),
        ("envelope", (-4.0, -2.0, 0.0), "envelope over ε = −4° … 0° (every 2°)"),
        ("envelope", (-4.0, 70.0), "envelope over ε = −4° … 70° (every 74°)"),
        ("envelope", (-4.0, 30.0, 70.0), "envelope over ε = −4°, 30°, 70°"),
        ("envelope", (12.5,), "envelope over ε = 12.5°"),
    ],
)
def test_a_scope_s_title_lists_uneven_elevations(name, elevations, title):
    """Once "every 34°" for −4°, 30°, 70°: the step between the first two."""
    assert Scope(name, elevations, (), {}).title == title
