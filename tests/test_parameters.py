"""Parameter sets: Table I's masses exactly, physical inertias, every number with a source."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from feeder import (
    CHARGE_FEEDER,
    PROJECTILE_FEEDER,
    InertiaError,
    InputError,
    LinkInertia,
    parameter_table,
)
from feeder.parameters import check_inertia

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
    assert any(math.isclose(value * 10, p, rel_tol=4e-16) for p in printed)


def test_devices_are_physical():
    PROJECTILE_FEEDER.check()
    CHARGE_FEEDER.check()


def test_charge_feeder_is_the_mirror_image():
    assert CHARGE_FEEDER.c == -PROJECTILE_FEEDER.c
    assert CHARGE_FEEDER.z5 == -PROJECTILE_FEEDER.z5
    assert CHARGE_FEEDER.swing == -PROJECTILE_FEEDER.swing
    assert CHARGE_FEEDER.L1 == PROJECTILE_FEEDER.L1 and CHARGE_FEEDER.d3 == PROJECTILE_FEEDER.d3
    assert CHARGE_FEEDER.payload.source.startswith("assumed")


@pytest.mark.parametrize(
    "mass, moments, reason",
    [
        (-1.0, (1.0, 1.0, 1.0), "positive"),
        (0.0, (1.0, 1.0, 1.0), "positive"),
        (1.0, (1.0, 1.0, -0.1), "positive definite"),
        (1.0, (1.0, 1.0, 2.0), "triangle"),
        (float("nan"), (1.0, 1.0, 1.0), "finite"),
        (1.0, (1.0, float("inf"), 1.0), "finite"),
    ],
)
def test_check_inertia_refuses_non_physical(mass, moments, reason):
    with pytest.raises(InertiaError, match=reason):
        check_inertia("some_link", mass, np.diag(moments))


def test_check_inertia_sees_rotated_tensors():
    # A valid rod rotated by 30° about z keeps its principal moments: still valid.
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    rotation = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    check_inertia("rod", 1.0, rotation @ np.diag([0.01, 1.0, 1.0]) @ rotation.T)
    with pytest.raises(InertiaError):
        check_inertia("bad", 1.0, rotation @ np.diag([0.1, 0.1, 1.0]) @ rotation.T)


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
