"""Rate columns of a motion table checked against its positions: contradictions refused (naming
the column, the times and rows, by how much), consistent tables accepted however they are
sampled and written."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from feeder.chain.readers.motion_table import read_motion
from feeder.exceptions import InputError

from ...conftest import REPO

T = np.linspace(0.0, 4.0, 401)
"""An excavator cylinder's 4 s stroke, sampled every 10 ms."""


def _table(folder: Path, columns: dict[str, np.ndarray], digits: str = "") -> Path:
    """A motion table of ``columns`` (``t`` first), each number written with the format
    ``digits`` ("" for its shortest exact form)."""
    path = folder / "motion.csv"
    rows = np.column_stack(list(columns.values()))
    text = [",".join(format(float(x), digits) if digits else repr(float(x)) for x in row)
            for row in rows]  # fmt: skip
    path.write_text(",".join(columns) + "\n" + "\n".join(text) + "\n")
    return path


def _refusal(path: Path) -> str:
    with pytest.raises(InputError) as info:
        read_motion(path, ("stroke",))
    assert "\n" not in str(info.value)
    return str(info.value)


def test_zero_speeds_beside_a_moving_stroke_are_refused(tmp_path):
    """The stroke moves 0.6 m in 4 s at 0.15 m/s while its v_ and a_ columns say 0 (once read
    as given: the cylinder forces lost 8–21 % of their peaks)."""
    zero = np.zeros_like(T)
    path = _table(
        tmp_path, {"t": T, "q_stroke": 1.5 + 0.15 * T, "v_stroke": zero, "a_stroke": zero}
    )
    message = _refusal(path)
    assert message.startswith(
        f"{path}: column 'v_stroke' contradicts 'q_stroke' between t = 0 s and 0.01 s (data rows "
        "1 to 2): 'q_stroke' changes by 0.15 per second there, 'v_stroke' says 0 (off by 0.15,"
    )


@pytest.mark.parametrize(
    "given, message",
    [
        (
            {"v_stroke": 0.15 * math.pi / 4 * np.sin(math.pi * T / 4), "a_stroke": 0 * T},
            "column 'a_stroke' contradicts 'v_stroke' between t = 0 s and 0.01 s",
        ),
        (
            {"a_stroke": 0 * T},
            "column 'a_stroke' contradicts 'q_stroke' between t = ",
        ),
        (
            {"v_stroke": np.degrees(0.15 * math.pi / 4 * np.sin(math.pi * T / 4))},
            "column 'v_stroke' contradicts 'q_stroke'",
        ),
        (
            {"v_stroke": 2 * 0.15 * math.pi / 4 * np.sin(math.pi * T / 4)},
            "column 'v_stroke' contradicts 'q_stroke'",
        ),
    ],
    ids=["zero-acceleration", "zero-acceleration-without-speed", "degrees", "twice"],
)
def test_rates_that_contradict_the_positions_are_refused(tmp_path, given, message):
    """A cosine stroke (0.3 m in 4 s) whose given rates are zero, in degrees, or twice its own."""
    stroke = 1.5 + 0.15 * (1.0 - np.cos(math.pi * T / 4))
    assert message in _refusal(_table(tmp_path, {"t": T, "q_stroke": stroke, **given}, ".6g"))


def _cosine(t: np.ndarray) -> dict[str, np.ndarray]:
    w = math.pi / 4
    return {
        "t": t,
        "q_stroke": 1.5 + 0.15 * (1.0 - np.cos(w * t)),
        "v_stroke": 0.15 * w * np.sin(w * t),
        "a_stroke": 0.15 * w**2 * np.cos(w * t),
    }


def _trapezoid(t: np.ndarray) -> dict[str, np.ndarray]:
    """A trapezoidal speed profile: ±4 m/s² for 0.25 s at each end, its steps between samples."""
    ramp, cruise = np.minimum(t, 0.25), np.clip(t - 0.25, 0.0, 0.5)
    brake = np.clip(t - 0.75, 0.0, 0.25)
    return {
        "t": t,
        "q_stroke": 2.0 * ramp**2 + cruise + brake - 2.0 * brake**2,
        "v_stroke": 4.0 * ramp - 4.0 * brake,
        "a_stroke": np.select([t < 0.25, t < 0.75], [4.0, 0.0], -4.0),
    }


def _sine(t: np.ndarray) -> dict[str, np.ndarray]:
    w = 2.0 * math.pi
    return {
        "t": t,
        "q_stroke": np.sin(w * t),
        "v_stroke": w * np.cos(w * t),
        "a_stroke": -(w**2) * np.sin(w * t),
    }


@pytest.mark.parametrize(
    "columns, digits",
    [
        (_cosine(T), ""),
        (_cosine(T), ".6g"),
        (_cosine(T), ".3g"),
        (_cosine(T), ".3f"),
        (_trapezoid(np.linspace(0.0, 1.0, 37)), ""),
        (_trapezoid(np.linspace(0.0, 1.0, 37)), ".3g"),
        (_sine(np.linspace(0.0, 1.0, 7)), ""),
        (_sine(np.sort(np.random.default_rng(3).uniform(0.0, 1.0, 50))), ""),
        (_sine(np.arange(0.0, 2.0, 1.0 / 60.0)), ".3f"),
    ],
    ids=[
        "exact",
        "6-digits",
        "3-digits",
        "millimetres",
        "trapezoid-speed",
        "trapezoid-speed-3-digits",
        "6-samples-a-period",
        "uneven-times",
        "60-Hz-log-to-the-ms",
    ],
)
@pytest.mark.parametrize("rates", ["va", "v", "a"])
def test_rates_that_agree_with_the_positions_are_taken(tmp_path, columns, digits, rates):
    """Rates of the same motion, given both or one of them, pass whatever the sampling (steps
    of the acceleration between samples, 6 samples a period, uneven times) and the digits."""
    given = {name: column for name, column in columns.items() if name[0] in f"tq{rates}"}
    table = read_motion(_table(tmp_path, given, digits), ("stroke",))
    assert table.x.shape == (columns["t"].size, 1)


def test_the_shipped_motion_tables_with_rates_are_taken():
    for path in sorted(REPO.glob("examples/*/motion.csv")):
        independent = tomllib.loads((path.parent / "closures.toml").read_text())["mechanism"][
            "independent"
        ]  # the crank of the four-bar and slider-crank, the dump hoist's body tilt
        assert read_motion(path, tuple(independent)).differentiated == ()
