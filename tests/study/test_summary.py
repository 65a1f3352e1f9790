"""The cycle summary: a signed peak is printed as max |x| with its sign, a vector's as max ‖x‖,
and a peak that looks implausible but follows from the parameters carries a note saying why."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from feeder.device import CHARGE_FEEDER, PROJECTILE_FEEDER, LinkInertia, load_feeder
from feeder.motion.laws import CycleSpec
from feeder.study.columns import VECTORS
from feeder.study.cycle_study import run_cycle_study

SPEC = CycleSpec(rate=200.0)
"""The loads are exact at each sample: a coarse rate is enough (no forward run)."""
PRINTED = 5e-4
"""[unit] The summary prints peaks with three decimals: half a unit of the last digit."""
LINEAR_IN_INERTIA = 1e-9
"""Relative: the grip moment I·α + ω × I·ω is linear in I; the same motion with moments ten
times larger gives ten times the moment, to round-off."""

PEAK_LINE = re.compile(
    r"^  peak (\w+)\s+max (\|x\||‖x‖) =\s+([\d.]+) (\S+)\s+(positive|negative|zero)?\s+at t"
)


def study(params, elevation_deg=-4.0):
    return run_cycle_study(load_feeder(params), math.radians(elevation_deg), SPEC, forward=False)


@pytest.fixture(scope="module")
def charge():
    return study(CHARGE_FEEDER)


@pytest.fixture(scope="module")
def projectile():
    return study(PROJECTILE_FEEDER)


def parsed(text: str) -> dict[str, tuple[str, float, str, str | None]]:
    return {
        m.group(1): (m.group(2), float(m.group(3)), m.group(4), m.group(5))
        for m in map(PEAK_LINE.match, text.splitlines())
        if m
    }


@pytest.mark.parametrize("device", ["charge", "projectile"])
def test_peaks_are_max_magnitudes_with_their_sign(request, device):
    """Independent of the peak code: max |x| and its sign read from the table's columns."""
    result = request.getfixturevalue(device)
    columns, lines = result.columns(), parsed(result.summary())
    vectors = {name for name, *_ in VECTORS}
    assert set(lines) == {peak.name for peak in result.peaks()}
    for name, (kind, size, unit, sign) in lines.items():
        values = columns[name] / (1e5 if unit == "bar" else 1.0)
        k = int(np.argmax(np.abs(values)))
        assert size == pytest.approx(abs(values[k]), abs=PRINTED), name
        if name in vectors:
            assert kind == "‖x‖" and sign is None, name
        else:
            assert kind == "|x|" and sign == ("positive" if values[k] > 0 else "negative"), name


def test_a_negative_peak_shows_its_size_and_sign(charge):
    """The mirrored charge feeder's forearm moment peaks negative: printed as its size."""
    kind, size, unit, sign = parsed(charge.summary())["forearm_torque"]
    assert charge.columns()["forearm_torque"].min() == pytest.approx(-size, abs=PRINTED)
    assert (kind, unit, sign) == ("|x|", "N·m", "negative")


def test_tiny_grip_moment_is_explained(projectile, charge):
    """Table I's projectile has 0.0131 kg·m² where a solid cylinder of its size has ~1.8: the
    note says so; the charge case (a uniform cylinder by construction) gets no note."""
    text = projectile.summary()
    assert "note: grip_moment" in text and "Table I" in text
    assert "uniform solid cylinder" in " ".join(text.split())
    assert "note:" not in charge.summary()


def test_the_note_is_true_the_grip_moment_scales_with_the_inertia(projectile):
    """What the note claims, checked: ten times the payload's moments, ten times the grip
    moment (same motion), so the small moment is the inertia's doing."""
    payload = PROJECTILE_FEEDER.payload
    heavier = LinkInertia(payload.mass, tuple(10.0 * m for m in payload.moments), "×10")
    scaled = study(dataclasses.replace(PROJECTILE_FEEDER, payload=heavier))
    base = projectile.columns()["grip_moment"]
    np.testing.assert_allclose(
        scaled.columns()["grip_moment"], 10.0 * base, rtol=LINEAR_IN_INERTIA, atol=0.0
    )
    assert "note: grip_moment" in scaled.summary()  # still 14× below the solid cylinder
