"""The parameter file (TOML): it round-trips every built-in device exactly, states the unit of
every number, and a bad file is refused with an error that names the file and the field."""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib

import numpy as np
import pytest

from feeder.device import DEVICES, PROJECTILE_FEEDER, FeederParameters, LinkInertia
from feeder.device.parameter_file import (
    DIGITS,
    parameters_sha256,
    parameters_toml,
    read_parameters,
)
from feeder.exceptions import InputError


@pytest.fixture
def written(tmp_path):
    path = tmp_path / "projectile.toml"
    path.write_text(parameters_toml(PROJECTILE_FEEDER), encoding="utf-8")
    return path


def edit(path, old: str, new: str):
    text = path.read_text(encoding="utf-8")
    assert re.search(old, text, flags=re.M), old
    path.write_text(re.sub(old, new, text, count=1, flags=re.M), encoding="utf-8")
    return path


def assert_close(read: FeederParameters, original: FeederParameters) -> None:
    """Every number within DIGITS (relative) of the original's, every text equal."""
    for field in dataclasses.fields(FeederParameters):
        mine, theirs = getattr(read, field.name), getattr(original, field.name)
        if isinstance(theirs, LinkInertia):
            assert mine.source == theirs.source
            np.testing.assert_allclose(
                [mine.mass, *mine.moments], [theirs.mass, *theirs.moments], rtol=DIGITS, atol=0
            )
        elif isinstance(theirs, str):
            assert mine == theirs
        else:  # an angle read back through radians(degrees): 2 ulp more
            assert mine == pytest.approx(theirs, rel=DIGITS, abs=1e-15), field.name


@pytest.mark.parametrize("name", sorted(DEVICES))
def test_round_trip_to_the_digits_and_then_exact(tmp_path, name):
    """Read back: every number within DIGITS; written again: the same file (so one hash per
    parameter set, however often it is read and written)."""
    path = tmp_path / f"{name}.toml"
    text = parameters_toml(DEVICES[name])
    path.write_text(text, encoding="utf-8")
    read = read_parameters(path)
    assert_close(read, DEVICES[name])
    assert parameters_toml(read) == text


def test_every_number_has_its_unit_in_a_comment():
    """Independent of the writer: every field of the dataclass appears, each number with the
    unit its metadata names, and every angle in degrees under its ``_deg`` key."""
    lines = parameters_toml(PROJECTILE_FEEDER).splitlines()
    for field in dataclasses.fields(FeederParameters):
        value = getattr(PROJECTILE_FEEDER, field.name)
        if isinstance(value, float):
            unit = field.metadata["unit"]
            key = f"{field.name}_deg" if unit == "rad" else field.name
            (line,) = [x for x in lines if x.startswith(f"{key} = ")]
            assert f"# [{'deg' if unit == 'rad' else unit}]" in line, line
            written = float(line.split("=", 1)[1].split("#")[0])
            expected = math.degrees(value) if unit == "rad" else value
            assert written == pytest.approx(expected, rel=DIGITS, abs=1e-12)
    sections = [x for x in lines if x.startswith("[")]
    assert sections == ["[cylinder]", "[piston]", "[arm]", "[forearm]", "[payload]"]
    assert sum("mass = " in x and "# [kg]" in x for x in lines) == 5
    assert sum("moments = " in x and "# [kg·m²]" in x for x in lines) == 5


def test_the_file_shows_the_numbers_a_user_types():
    """Issue 19: ``b = 0.04999999999999999`` and angles in radians, once written for a user to
    edit; now the shortest decimals and degrees."""
    data = tomllib.loads(parameters_toml(PROJECTILE_FEEDER))
    assert data["payload"]["mass"] == 43.5
    assert data["swing_deg"] == 90.0 and data["elevation_min_deg"] == -4.0
    assert data["b"] == 0.05 and data["d"] == 0.009
    assert "swing" not in data
    text = parameters_toml(PROJECTILE_FEEDER)
    assert not re.search(r"\d{9}", text.split("[cylinder]")[0]), "a long decimal was written"


def test_a_file_with_angles_in_radians_is_refused(written):
    """A parameter file from before the degrees: refused, naming the key it lacks."""
    edit(written, r"^swing_deg = 90\.0 ", "swing = 1.5707963267948966 ")
    with pytest.raises(InputError, match="unknown field 'swing'"):
        read_parameters(written)


def test_hash_identifies_the_parameter_set(written):
    assert parameters_sha256(read_parameters(written)) == parameters_sha256(PROJECTILE_FEEDER)
    heavier = dataclasses.replace(
        PROJECTILE_FEEDER, payload=LinkInertia(52.2, PROJECTILE_FEEDER.payload.moments, "x")
    )
    assert parameters_sha256(heavier) != parameters_sha256(PROJECTILE_FEEDER)


def test_an_edit_is_read(written):
    edit(written, r"^mass = 43\.5 ", "mass = 52.2 ")
    edit(written, r"^d3 = 0\.19 ", "d3 = 0.191 ")
    params = read_parameters(written)
    assert params.payload.mass == 52.2 and params.d3 == 0.191
    assert_close(dataclasses.replace(params, payload=PROJECTILE_FEEDER.payload, d3=0.19),
                 PROJECTILE_FEEDER)  # fmt: skip


def test_an_integer_is_a_number(written):
    edit(written, r"^phi3_load_deg = 0\.0 ", "phi3_load_deg = 0 ")
    assert read_parameters(written).phi3_load == 0.0


@pytest.mark.parametrize(
    "old, new, message",
    [
        (r"^d3 = 0\.19 ", 'd3 = "0.19" ', r"d3 must be a number \[m\], got '0\.19'"),
        (r"^d3 = 0\.19 ", "d3 = true ", r"d3 must be a number \[m\], got True"),
        (r"^d3 = 0\.19 ", "d3 = nan ", r"d3 must be finite \[m\]"),
        (r"^d3 = 0\.19 ", "d3 = -0.19 ", "d3 must be positive"),
        (r"^d3 = 0\.19 .*\n", "", "missing field 'd3'"),
        (r"^d3 = 0\.19 ", "d_3 = 0.19 ", "unknown field 'd_3'"),
        (r"^mass = 43\.5 ", "mass = -43.5 ", "link 'projectile': mass"),
        (r"^mass = 43\.5 ", 'mass = "heavy" ', r"payload\.mass must be a number \[kg\]"),
        (r"^moments = \[0\.01312", "moments = [0.01312, 1.0", r"payload\.moments must be three"),
        (r"^moments = \[0\.01312", "moments = [1.0", "link 'projectile'.*triangle"),
        (r"^source = \"Table I\"$", "", r"missing field 'source' in table \[forearm\]"),
        (
            r"^\[payload\]$",
            "[payload]\ncolour = 1",
            r"unknown field 'colour' in table \[payload\]",
        ),
        (r"^name = ", "name = 3 #", "name must be a string"),
        (r"^name = .*$", 'name = "../../x"', "name must be letters, digits.*got '../../x'"),
        (r"^name = .*$", 'name = ".hidden"', "name must be letters, digits.*got '.hidden'"),
        (r"^name = .*$", 'name = "a b"', "name must be letters, digits.*got 'a b'"),
        (r"^name = .*$", 'name = ""', "name must be letters, digits.*got ''"),
        (r"^L2 = 0\.28 ", "L2 = 0.9 ", "cannot be assembled"),
        (r"^d3 = 0\.19 ", "d3 = ", "not a TOML parameter file"),
    ],
)
def test_bad_file_names_the_file_and_the_field(written, old, new, message):
    edit(written, old, new)
    with pytest.raises(InputError, match=message) as info:
        read_parameters(written)
    assert str(written) in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="parameter file not found"):
        read_parameters(tmp_path / "nope.toml")
    with pytest.raises(InputError, match="parameter file .* is a folder"):
        read_parameters(tmp_path)


def test_not_utf8(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes("name = 'é'".encode("latin-1"))
    with pytest.raises(InputError, match="cannot read the parameter file"):
        read_parameters(path)


def test_a_name_with_dots_and_dashes_is_read(written):
    edit(written, r"^name = .*$", 'name = "mk-2.1_b"')
    assert read_parameters(written).name == "mk-2.1_b"
