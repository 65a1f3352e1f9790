"""The sweep grid (feeder.study.grid, grid_file): the TOML file, its cases, and every refusal
before any cycle is computed."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from feeder.device import CHARGE_FEEDER, PROJECTILE_FEEDER
from feeder.dynamics.servo import ServoGains
from feeder.exceptions import ElevationError, FeederError, InputError
from feeder.motion.laws import CycleSpec
from feeder.study.grid import Variant, elevation_range, fingerprint, make_grid
from feeder.study.grid_file import read_grid
from feeder.study.retrofit import retrofit

EXAMPLE = """
devices = ["projectile", "charge"]
elevations = {start = -4, stop = 70, step = 2}
rate = 500.0
durations = [1.0, 1.0, 2.5]

[[variants]]
name = "reference"

[[variants]]
name = "heavier"
mass_factor = 1.2
length_factor = 1.15

[[variants]]
name = "pivot_up"
L2 = 0.29
"""


def _grid_file(tmp_path, text: str):
    path = tmp_path / "grid.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_documented_example(tmp_path):
    grid = read_grid(_grid_file(tmp_path, EXAMPLE))
    assert list(grid.devices) == ["projectile", "charge"]
    np.testing.assert_array_equal(grid.elevations_deg, np.arange(-4, 71, 2))
    assert grid.spec == CycleSpec(durations=(1.0, 1.0, 2.5), rate=500.0)
    cases = grid.cases()
    assert len(cases) == 2 * 3 * 38
    first = cases[0]
    assert first.key == ("projectile", "reference", -4.0)
    assert first.elevation == math.radians(-4.0)  # as `feeder cycle --elevation -4` has it
    assert first.params == PROJECTILE_FEEDER
    by_key = {case.key: case for case in cases}
    assert by_key[("charge", "heavier", 30.0)].params == retrofit(CHARGE_FEEDER, 1.2, 1.15)
    assert by_key[("projectile", "pivot_up", 70.0)].params == replace(PROJECTILE_FEEDER, L2=0.29)


def test_defaults_are_the_whole_range_every_degree():
    grid = make_grid()
    np.testing.assert_array_equal(grid.elevations_deg, np.arange(-4, 71))
    assert [v.name for v in grid.variants] == ["reference"]
    assert list(grid.devices) == ["projectile"] and grid.spec == CycleSpec()


def test_elevation_range_has_whole_numbers_and_includes_the_stop():
    values = elevation_range(-4.0, 70.0, 0.1)
    assert values.size == 741 and values[-1] == pytest.approx(70.0, abs=1e-12)
    assert np.all(elevation_range(-4, 70, 1) == np.arange(-4, 71))  # exact, not accumulated
    assert list(elevation_range(10, 10, 5)) == [10.0]
    # Tenths read as typed: the shortest decimal of each value is k/10 itself.
    tenths = [repr(float(x)) for x in elevation_range(0, 1, 0.1)]
    assert tenths == [repr(k / 10) for k in range(11)]


@pytest.mark.parametrize(
    "start, stop, step", [(0, 10, 0), (0, 10, -1), (10, 0, 1), (0, float("nan"), 1)]
)
def test_elevation_range_refuses(start, stop, step):
    with pytest.raises(InputError, match="elevation"):
        elevation_range(start, stop, step)


def test_fingerprint_tells_parameters_and_timing_apart():
    spec = CycleSpec()
    same = fingerprint(replace(PROJECTILE_FEEDER), CycleSpec())
    assert fingerprint(PROJECTILE_FEEDER, spec) == same
    assert fingerprint(replace(PROJECTILE_FEEDER, L2=0.3), spec) != same
    assert fingerprint(PROJECTILE_FEEDER, CycleSpec(rate=999.0)) != same


@pytest.mark.parametrize(
    "text, message",
    [
        ("devices = ['mortar']", "unknown devices"),
        ("devices = 'projectile'", "list of device names"),
        ("devices = []", "at least one device"),
        ("elevations = []", "at least one elevation"),
        ("elevations = {start = 0}", "start and stop"),
        ("elevations = 'all'", "a list or"),
        ("elevations = ['ten']", "elevation"),
        ("rate = -1.0", "sample rate"),
        ("colour = 'red'", "unknown keys"),
        ("variants = 'heavy'", "array of tables"),
        ("[[variants]]\nmass_factor = 1.2", "must be a table with a name"),
        ("[[variants]]\nname = 'a b'", "variant name"),
        ("[[variants]]\nname = 'x'\nweight = 2.0", "unknown key 'weight'"),
        ("[[variants]]\nname = 'x'\nL2 = 'high'", "L2"),
        ("[[variants]]\nname = 'x'\n[[variants]]\nname = 'x'", "unique"),
        ("elevations = [\n", "not a TOML"),
        ("[[variants]]\nname = 'x'\nforward = 'force-rule'", 'is "controlled"'),
        ("[[variants]]\nname = 'x'\nservo = {bandwidth_hz = 8.0}", "add forward"),
        ("[[variants]]\nname = 'x'\nforward = 'controlled'\nservo = 3", "servo must be a table"),
        ("[[variants]]\nname = 'x'\nforward = 'controlled'\nservo = {gain = 1}", "unknown servo"),
        ("[[variants]]\nname = 'x'\nforward = 'controlled'\nservo = {damping = 0}", "damping"),
    ],
)
def test_bad_grid_files_name_the_file_and_the_fault(tmp_path, text, message):
    path = _grid_file(tmp_path, text)
    with pytest.raises(InputError, match=message) as info:
        read_grid(path)
    assert str(path) in str(info.value)


def test_elevation_outside_a_device_range(tmp_path):
    with pytest.raises(ElevationError, match="outside"):
        read_grid(_grid_file(tmp_path, "elevations = [-4, 75]"))


def test_a_variant_that_does_not_assemble_is_refused_before_any_cycle():
    """The arm pivot 20 mm higher needs more than the cylinder's stroke at the end of the
    arm's travel: refused by the device's check, naming the device and the variant."""
    with pytest.raises(FeederError, match="device 'projectile', variant 'pivot_up'.*stroke"):
        make_grid(variants=[Variant("pivot_up", {"L2": 0.3})])


def test_missing_grid_file(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        read_grid(tmp_path / "missing.toml")


def test_variant_keeps_floats_and_refuses_text():
    assert Variant("x", {"L2": 1}).changes == (("L2", 1.0),)
    with pytest.raises(InputError, match="L2"):
        Variant("x", {"L2": "0.3"})
    with pytest.raises(InputError, match="unknown key"):
        Variant("x", {"name": "y"})


def test_a_controlled_variant_carries_its_servo_into_its_cases(tmp_path):
    """forward = "controlled" with a servo table: the cases carry those position loops, and
    their hash differs from the same variant's without the run (a resumed table tells them
    apart); a variant without the run keeps the hash it had before the key existed."""
    text = (
        "elevations = [30]\n[[variants]]\nname = 'plain'\n"
        "[[variants]]\nname = 'loop'\nforward = 'controlled'\nservo = {bandwidth_hz = 8.0}\n"
    )
    plain, loop = read_grid(_grid_file(tmp_path, text)).cases()
    assert plain.servo is None
    assert loop.servo == ServoGains(bandwidth_hz=8.0)
    assert replace(loop, variant="plain").sha256 != plain.sha256
    assert replace(loop, variant="plain", servo=None).sha256 == plain.sha256
