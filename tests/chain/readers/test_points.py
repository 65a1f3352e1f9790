"""``[[point]]`` tables of a mechanism file: read strictly, each refusal one line naming the point
(feeder.chain.readers.points), and their frames and bodies checked against the model when it is
loaded (feeder.chain.model.points)."""

from __future__ import annotations

import pytest

from feeder.chain import load_mechanism, read_spec
from feeder.chain.model.points import Point
from feeder.exceptions import InputError

from ...conftest import REPO, four_bar_file

FOUR_BAR = REPO / "examples" / "four_bar"


def write(tmp_path, points: str):
    return four_bar_file(tmp_path, points)


def test_points_are_read(tmp_path):
    path = write(
        tmp_path,
        '[[point]]\nname = "P"\nframe = "rocker_tip"\n\n'
        '[[point]]\nname = "C"\nbody = "coupler"\noffset = [0.06, 0.0, 0.0]\n',
    )
    spec = read_spec(path)
    assert spec.points == (
        Point("P", "rocker_tip", (0.0, 0.0, 0.0), False),
        Point("C", "coupler", (0.06, 0.0, 0.0), True),
    )
    load_mechanism(spec)  # the model has both


@pytest.mark.parametrize(
    "points, message",
    [
        ('[[point]]\nframe = "rocker_tip"\n', r'name = "…" is required'),
        ('[[point]]\nname = "P"\n', "give one of frame"),
        ('[[point]]\nname = "P"\nframe = "rocker_tip"\nbody = "rocker"\n', "give one of frame"),
        (
            '[[point]]\nname = "P"\nframe = "a"\n[[point]]\nname = "P"\nframe = "b"\n',
            "given twice",
        ),
        ('[[point]]\nname = "P"\nbody = "rocker"\noffset = [1, 2]\n', "offset must be 3 numbers"),
        ('[[point]]\nname = "P"\nbody = "rocker"\noffset = [1, nan, 2]\n', r"offset \[m\]"),
        ('[[point]]\nname = "P"\nbody = "rocker"\noffset = "up"\n', r"offset \[m\]"),
        ('[[point]]\nname = "P"\nframe = "rocker_tip"\nspeed = 1\n', "unknown keys"),
        ("point = 3\n", "must be"),
    ],
    ids=["no-name", "no-frame", "frame-and-body", "twice", "short", "nan", "text", "key", "type"],
)
def test_bad_points_are_refused_in_one_line(tmp_path, points, message):
    path = write(tmp_path, points) if not points.startswith("point") else None
    if path is None:  # a bare key after the tables would belong to the last one: put it first
        path = tmp_path / "closures.toml"
        path.write_text(points + (FOUR_BAR / "closures.toml").read_text(encoding="utf-8"))
    with pytest.raises(InputError, match=message) as info:
        read_spec(path)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "points, message",
    [
        ('[[point]]\nname = "P"\nframe = "rocker_tp"\n', r"no frame 'rocker_tp' .*'rocker_tip'\?"),
        ('[[point]]\nname = "P"\nbody = "rockr"\n', r"'P': body: no frame 'rockr' .*'rocker'\?"),
        ('[[point]]\nname = "P"\nbody = "rocker_joint"\n', "not a body"),
    ],
)
def test_points_off_the_model_are_refused_when_it_is_loaded(tmp_path, points, message):
    spec = read_spec(write(tmp_path, points))
    with pytest.raises(InputError, match=message) as info:
        load_mechanism(spec)
    assert "\n" not in str(info.value) and "mechanism file's [[point]] 'P'" in str(info.value)
