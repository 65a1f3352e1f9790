"""Type confusion at the public entry points: a number typed as text or as a truth value, a
device name in a list, is refused with a feeder error naming the value (numpy would read "0.5"
and True as numbers and run a whole study with them)."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

import feeder as api
from feeder.device import PROJECTILE_FEEDER, LinkInertia
from feeder.exceptions import ElevationError, FeederError, InputError, UrdfError
from feeder.validation import (
    check_elevation,
    check_elevations_deg,
    check_file,
    check_number,
    check_path,
)


@pytest.mark.parametrize(
    "bad, match",
    [
        ("0.5", "text '0.5'"),
        (True, "truth value True"),
        (np.True_, "truth value"),
        ([0.5], "one number"),
        (None, "numeric"),
        (float("nan"), "finite"),
    ],
)
@pytest.mark.parametrize("entry", ["run_cycle_study", "feeding_cycle"])
def test_elevation_must_be_one_number(feeder, entry, bad, match):
    with pytest.raises(InputError, match=f"elevation.*{match}"):
        getattr(api, entry)(feeder, bad)


def test_text_length_in_parameters_is_refused_before_any_study():
    with pytest.raises(InputError, match="c must be numeric, got the text '0.05'"):
        api.load_feeder(dataclasses.replace(PROJECTILE_FEEDER, c="0.05"))


@pytest.mark.parametrize("device", [["projectile"], ("projectile",), 1, None])
def test_device_must_be_a_name_or_parameters(device):
    with pytest.raises(InputError, match="unknown device"):
        api.load_feeder(device)


def test_text_mass_is_refused_with_the_link_name():
    payload = LinkInertia("43.5", PROJECTILE_FEEDER.payload.moments, "typed as text")
    with pytest.raises(InputError, match="link 'projectile': mass .* text '43.5'"):
        api.load_feeder(dataclasses.replace(PROJECTILE_FEEDER, payload=payload))


@pytest.mark.parametrize(
    "value, expected", [(0.5, 0.5), (np.float32(0.25), 0.25), (3, 3.0), (np.int64(-4), -4.0)]
)
def test_check_number_accepts_real_numbers(value, expected):
    assert check_number("x", value) == expected


@pytest.mark.parametrize("bad", ["1", b"1", True, np.False_, [1.0], np.ones(2), 1j, {"x": 1}])
def test_check_number_refuses_everything_else(bad):
    with pytest.raises(FeederError, match="x must be"):
        check_number("x", bad)


def test_check_elevations_deg_gives_floats_in_the_range():
    limits = PROJECTILE_FEEDER.elevation_limits
    assert check_elevations_deg(np.array([-4, 30, 70]), limits) == [-4.0, 30.0, 70.0]
    assert check_elevations_deg(30, limits) == [30.0]
    assert check_elevations_deg([80.0], None) == [80.0]  # no limits: numbers only


@pytest.mark.parametrize(
    "bad, error, match",
    [
        (["x"], InputError, "must be numeric, got the text 'x'"),
        ("30", InputError, "must be numeric, got the text '30'"),
        ([30.0, True], InputError, "truth value"),
        ([30.0, math.nan], InputError, "must be finite"),
        ([], InputError, "at least one elevation"),
        ([30.0, 71.0], ElevationError, "elevation 71° is outside"),
    ],
)
def test_check_elevations_deg_refuses(bad, error, match):
    with pytest.raises(error, match=match) as info:
        check_elevations_deg(bad, PROJECTILE_FEEDER.elevation_limits)
    assert type(info.value) is error


@pytest.mark.parametrize(
    "bad, match", [("", "empty"), ("   ", "empty"), (3, "a path"), (None, "a path")]
)
def test_check_path_refuses_empty_and_non_paths(bad, match):
    """An empty path is the current folder to pathlib: ``--out ""`` wrote there."""
    with pytest.raises(InputError, match=match):
        check_path("out", bad)


def test_check_path_accepts_text_and_paths(tmp_path):
    assert check_path("out", "results") == Path("results")
    assert check_path("out", tmp_path) == tmp_path


def test_check_file_says_missing_or_folder(tmp_path):
    """A folder given for a file is named as one, not reported missing (``--params /tmp`` said
    "parameter file not found: /tmp"); the reader's own error class is kept."""
    (tmp_path / "a.toml").write_text("")
    assert check_file("parameter file", str(tmp_path / "a.toml")) == tmp_path / "a.toml"
    with pytest.raises(InputError, match=r"parameter file not found: .*b\.toml$"):
        check_file("parameter file", tmp_path / "b.toml")
    with pytest.raises(UrdfError, match="URDF file .* is a folder, not a file") as info:
        check_file("URDF file", tmp_path, UrdfError)
    assert type(info.value) is UrdfError
    with pytest.raises(InputError, match="a path"):
        check_file("URDF file", None, UrdfError)


@pytest.mark.parametrize(
    "call",
    [
        lambda f: __import__("feeder").workspace(f, True),
        lambda f: __import__("feeder").elevation_sweep(f, [True], progress=False),
        lambda f: __import__("feeder").retrofit(f.params, True, 1.0),
        lambda f: __import__("feeder").CycleSpec(rate=True),
    ],
    ids=["workspace", "sweep", "retrofit", "rate"],
)
def test_truth_values_are_not_numbers(feeder, call):
    with pytest.raises(InputError, match="truth value"):
        call(feeder)


def test_a_bad_number_is_shown_as_the_user_typed_it():
    """``--elevation nan`` once said ``got np.float64(nan)``."""
    from feeder.validation import check_finite

    for value, shown in ((float("nan"), "got nan"), (np.array([1.0, np.inf]), "got inf")):
        with pytest.raises(InputError, match=shown) as error:
            check_finite("elevation [deg]", value)
        assert "np." not in str(error.value)


@pytest.mark.parametrize("degrees, shown", [(70.0001, "70.0001°"), (1e308, "1e+308°")])
def test_an_elevation_just_or_far_outside_the_range_is_shown_as_given(degrees, shown):
    """Enough digits to see why 70.0001° is refused, and no 300-digit number for 1e308°."""
    with pytest.raises(
        ElevationError, match=rf"^elevation {re.escape(shown)} is outside .* \[-4°, 70°\]$"
    ):
        check_elevation(math.radians(degrees), (math.radians(-4.0), math.radians(70.0)))


def test_did_you_mean_names_the_nearest_name_or_nothing():
    from feeder.validation import did_you_mean

    assert (
        did_you_mean("crank_jiont", ["rocker_joint", "crank_joint"])
        == "did you mean 'crank_joint'? "
    )
    assert did_you_mean("zzz", ["crank_joint"]) == ""
