"""Parameter sets: Table I's masses exactly, physical inertias, every number with a source, and
the checks that refuse a bad set (its numbers here, its arm travel through the loop)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from feeder.device.builtin import CHARGE_FEEDER, DEVICES, PROJECTILE_FEEDER
from feeder.device.loop import check_device
from feeder.device.parameters import FeederParameters, LinkInertia
from feeder.device.table import parameter_table
from feeder.exceptions import InertiaError, InputError, UnreachablePoseError

TABLE_I_MASSES = {
    "cylinder": 4.117,
    "piston": 2.092,
    "arm": 18.663,
    "forearm": 16.077,
    "projectile": 43.500,
}
"""Table I masses [kg], typed from the paper."""

TABLE_I_MOMENTS_AS_PRINTED = {
    "cylinder": (3.504e-2, 2.391e-2, 3.511e-2),
    "piston": (1.054e-2, 4.160e-2, 1.058e-2),
    "arm": (0.238e-2, 5.036e-2, 0.278e-2),
    "forearm": (0.262e-2, 0.284e-2, 0.531e-2),
    "projectile": (1.312e-2, 0.143e-2, 1.312e-2),
}
"""Table I moments (Ixx, Iyy, Izz) [kg·m²] as printed, typed from the paper."""
FEW_ULPS = 4e-16
"""Relative rounding of one multiplication by 10 and of the two decimal literals: ~2 ulps."""


def test_table_i_masses_exact():
    for link, inertia in PROJECTILE_FEEDER.links().items():
        assert inertia.mass == TABLE_I_MASSES[link]


@pytest.mark.parametrize("link", ["piston", "arm"])
def test_printed_table_i_inertias_of_links_2_and_3_are_refused(link):
    with pytest.raises(InertiaError, match=link) as info:
        LinkInertia(TABLE_I_MASSES[link], TABLE_I_MOMENTS_AS_PRINTED[link], "printed").check(link)
    assert info.value.link == link


@pytest.mark.parametrize("link", ["cylinder", "forearm", "projectile"])
def test_physical_table_i_moments_kept_as_printed(link):
    used = PROJECTILE_FEEDER.links()[link].moments
    printed = TABLE_I_MOMENTS_AS_PRINTED[link]
    # Cylinder and piston: the table's x/y are exchanged into the link frame (a relabelling).
    assert sorted(used) == sorted(printed)
    assert used[2] == printed[2]  # the pivot axis z is common to both frames


@pytest.mark.parametrize("link", ["piston", "arm"])
def test_corrections_are_one_exponent_digit(link):
    used, printed = PROJECTILE_FEEDER.links()[link].moments, TABLE_I_MOMENTS_AS_PRINTED[link]
    changed = set(used) - set(printed)
    assert len(changed) == 1
    (value,) = changed
    # ×10 rounds in binary floating point: compare to a few ulps.
    assert any(math.isclose(value * 10, p, rel_tol=FEW_ULPS) for p in printed)


@pytest.mark.parametrize("name", sorted(DEVICES))
def test_devices_are_physical(name):
    """Every built-in device passes its own checks and the loop's over the whole travel."""
    DEVICES[name].check()
    check_device(DEVICES[name])


def test_charge_feeder_is_the_mirror_image():
    assert CHARGE_FEEDER.c == -PROJECTILE_FEEDER.c
    assert CHARGE_FEEDER.z5 == -PROJECTILE_FEEDER.z5
    assert CHARGE_FEEDER.swing == -PROJECTILE_FEEDER.swing
    assert CHARGE_FEEDER.L1 == PROJECTILE_FEEDER.L1 and CHARGE_FEEDER.d3 == PROJECTILE_FEEDER.d3
    assert CHARGE_FEEDER.payload.source.startswith("assumed")


def test_every_number_has_a_unit_and_source():
    rows = parameter_table(PROJECTILE_FEEDER)
    names = {row[0] for row in rows}
    for field in dataclasses.fields(PROJECTILE_FEEDER):
        if isinstance(getattr(PROJECTILE_FEEDER, field.name), float):
            assert field.name in names
    for name, value, _unit, source in rows:
        assert source, name
        assert value
    assert any(source.startswith("Table I") for *_, source in rows)
    assert any(source.startswith("assumed") for *_, source in rows)


def test_nan_parameter_is_refused():
    with pytest.raises(InputError, match="d3"):
        dataclasses.replace(PROJECTILE_FEEDER, d3=float("nan")).check()


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"d3": 0.0}, "d3 must be positive, got 0.0 m"),
        ({"d2": -0.1}, "d2 must be positive, got -0.1 m"),
        ({"e5": 0.0}, "e5 must be positive"),
        ({"payload_length": -0.7}, "payload_length must be positive, got -0.7"),
        ({"pinion_radius": 0.0}, "pinion_radius must be positive"),
        ({"a": 0.4, "b": -0.5}, r"a1 = a \+ b must be positive, got -0.0999"),
        ({"l3": -0.2}, "l3 .* must not be negative, got -0.2 m"),
        ({"rod_diameter": 0.06}, "rod diameter 0.06 m must be smaller than the bore .* 0.05 m"),
        ({"r2_max": 0.2}, "r2_min = 0.2304 m must be smaller than r2_max = 0.2 m"),
        ({"phi1_min": 3.0}, "phi1_min_deg = 171.887° must be smaller than phi1_max_deg"),
        ({"phi3_max": -0.1}, "phi3_min_deg = -5° must be smaller than phi3_max_deg = -5.72958°"),
        ({"elevation_max": -0.1}, "elevation_min_deg = -4° .* elevation_max_deg = -5.72958°"),
        ({"phi4_limit": 0.0}, "phi4_limit must be positive, got 0.0"),
        ({"swing": 10.0}, "swing 572.958° is outside the forearm's end stops ±100.000°"),
        ({"swing": -2.0}, "swing -114.592° is outside"),
    ],
)
def test_out_of_range_parameters_are_refused(changes, message):
    with pytest.raises(InputError, match=message):
        dataclasses.replace(PROJECTILE_FEEDER, **changes).check()


@pytest.mark.parametrize(
    "changes, message",
    [
        # The loading pose needs r2 = 0.2404 m: the stroke is moved past it.
        ({"r2_min": 0.25}, r"φ3 = 0.000° needs piston position r2 = 0.2404 m, outside"),
        # At −20° the arm would turn 110°, past its end stop at 100°.
        (
            {"elevation_min": math.radians(-20.0)},
            "φ3 = 100.0[0-9]*° is outside the arm's end stops",
        ),
        ({"phi1_max": math.radians(130.0)}, r"φ1 = 136.975°, outside its swing"),
    ],
)
def test_unreachable_cycle_is_refused(changes, message):
    """The arm travel is the loop's to check: the parameter set's own numbers are fine."""
    unreachable = dataclasses.replace(PROJECTILE_FEEDER, **changes)
    unreachable.check()
    with pytest.raises(UnreachablePoseError, match=message) as info:
        check_device(unreachable)
    assert "arm travel [0.00°," in str(info.value)


def test_travel_through_the_toggle_is_refused():
    """Loading at φ3 = −30° puts the toggle (φ3 ≈ −29.7°, B, the arm pivot and the pin in line)
    on the travel, with the end stops opened so that every pose is otherwise reachable."""
    toggle = dataclasses.replace(
        PROJECTILE_FEEDER,
        phi3_min=math.radians(-45.0),
        r2_min=0.15,
        phi3_load=math.radians(-30.0),
        elevation_max=math.radians(30.0),
    )
    toggle.check()
    with pytest.raises(InputError, match=r"transmission angle [0-9.]+° .*φ3 = -29"):
        check_device(toggle)


def float_fields() -> list[str]:
    """Names of the float fields of FeederParameters (annotations are strings here)."""
    return [f.name for f in dataclasses.fields(FeederParameters) if f.type == "float"]


def test_every_float_field_is_checked():
    """The refusal below covers the geometry, the motion, the limits and the drives alike."""
    names = float_fields()
    for name in ("L1", "c", "d3", "phi3_load", "swing", "r2_max", "pinion_radius"):
        assert name in names
    assert "name" not in names and "payload" not in names


@pytest.mark.parametrize("name", float_fields())
@pytest.mark.parametrize("bad", ["0.05", True], ids=["text", "bool"])
def test_float_fields_refuse_text_and_booleans(name, bad):
    """numpy would read "0.05" and True as numbers; a parameter typed so is a mistake."""
    with pytest.raises(InputError, match=f"parameters 'projectile': {name} must be"):
        dataclasses.replace(PROJECTILE_FEEDER, **{name: bad}).check()


def test_text_offset_is_refused():
    """The example of the issue: an offset of either sign given as text."""
    with pytest.raises(InputError, match=r"c must be numeric, got the text '0\.05'"):
        dataclasses.replace(PROJECTILE_FEEDER, c="0.05").check()
    with pytest.raises(InputError, match="c must be a number, got the truth value True"):
        dataclasses.replace(PROJECTILE_FEEDER, c=True).check()
    with pytest.raises(InputError, match="c must be a number, got the truth value"):
        dataclasses.replace(PROJECTILE_FEEDER, c=np.False_).check()
    with pytest.raises(InputError, match=r"c must be one number, got \[0\.05, 0\.05\]"):
        dataclasses.replace(PROJECTILE_FEEDER, c=[0.05, 0.05]).check()
    dataclasses.replace(PROJECTILE_FEEDER, c=0.05).check()  # the number itself is fine


@pytest.mark.parametrize(
    "mass, moments",
    [
        ("18.663", (0.238e-2, 0.5036e-2, 0.278e-2)),
        (18.663, ("0.238e-2", "0.5036e-2", "0.278e-2")),
        (True, (0.238e-2, 0.5036e-2, 0.278e-2)),
    ],
    ids=["text-mass", "text-moments", "bool-mass"],
)
def test_link_inertia_refuses_text_and_booleans(mass, moments):
    """Like the float fields: a mass or moment typed as text or a truth value is refused with
    a feeder error (not numpy's TypeError, not 1 kg)."""
    arm = LinkInertia(mass, moments, "typed")
    with pytest.raises((InputError, InertiaError), match="arm"):
        dataclasses.replace(PROJECTILE_FEEDER, arm=arm).check()
