"""The Extended-URDF side-file (YAML) within its limits (size, nesting, aliases), and a loop
listed twice. Each refusal is one line that names the file (and the limit)."""

from __future__ import annotations

from pathlib import Path

import pytest

from feeder.chain.readers.extended_urdf import YAML_MAX_VALUES
from feeder.chain.readers.mechanism import read_spec
from feeder.chain.readers.spec import SIDE_FILE_MAX_BYTES, SIDE_FILE_MAX_DEPTH
from feeder.exceptions import FeederWarning, InputError

VALID = "closed_loop: [[A, B]]\ntype: [6d]\nname_mot: [m]\n"
"""A side-file that reads (its model, robot.urdf beside it, exists in each test's folder)."""


def _side_file(folder: Path, text: str) -> Path:
    (folder / "robot.urdf").write_text("<robot name='r'/>")
    path = folder / "robot.yaml"
    path.write_text(text)
    return path


def _refusal(path: Path) -> str:
    with pytest.raises(InputError) as info:
        read_spec(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ") and "\n" not in message
    return message


def _laughs(levels: int) -> str:
    """``closed_loop`` built from ``levels`` levels of 9 aliases: 9**levels names."""
    lines = ["l0: &l0 [x, x, x, x, x, x, x, x, x]"]
    lines += [f"l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]" for i in range(1, levels)]
    return "\n".join(lines) + f"\nclosed_loop: *l{levels - 1}\nname_mot: [m]\n"


def test_a_valid_side_file_is_read(tmp_path):
    spec = read_spec(_side_file(tmp_path, VALID))
    assert [(c.frame_a, c.frame_b, c.kind) for c in spec.closures] == [("A", "B", "weld")]


def test_aliases_that_expand_beyond_the_limit_are_refused(tmp_path):
    """6 levels of 9 aliases make 9⁶ = 531 441 names (the "billion laughs" of 9 levels would
    make 9⁹ and never finish): refused while composing, before a value is built."""
    assert 9**6 > YAML_MAX_VALUES
    message = _refusal(_side_file(tmp_path, _laughs(6)))
    assert f"aliases expand the value at line 6 to more than {YAML_MAX_VALUES} values" in message


def test_aliases_within_the_limit_are_read(tmp_path):
    text = "pair: &p [A, B]\nclosed_loop: [*p]\ntype: &t [6d]\nname_mot: [m]\n"
    with pytest.warns(FeederWarning, match=r"keys \['pair'\] are not used"):
        spec = read_spec(_side_file(tmp_path, text))
    assert [(c.frame_a, c.frame_b) for c in spec.closures] == [("A", "B")]


def test_an_alias_inside_its_own_anchor_is_refused(tmp_path):
    message = _refusal(_side_file(tmp_path, "closed_loop: &a [*a]\nname_mot: [m]\n"))
    assert "the alias at line 1 is inside its anchor" in message


@pytest.mark.parametrize("depth", [SIDE_FILE_MAX_DEPTH, 5000])
def test_deep_nesting_is_refused(tmp_path, depth):
    """Nested just past the limit, or 5000 levels (PyYAML's recursion ran out of stack there)."""
    text = f"closed_loop: {'[' * depth}{']' * depth}\nname_mot: [m]\n"
    message = _refusal(_side_file(tmp_path, text))
    assert f"nested deeper than {SIDE_FILE_MAX_DEPTH} levels at line 1" in message


def test_nesting_up_to_the_limit_is_read_and_checked(tmp_path):
    """The document is level 1: lists nested down to the limit pass the loader and meet the
    side-file's own checks."""
    depth = SIDE_FILE_MAX_DEPTH - 1
    text = f"closed_loop: {'[' * depth}{']' * depth}\nname_mot: [m]\n"
    assert "'closed_loop' must be a list of pairs" in _refusal(_side_file(tmp_path, text))


def test_a_file_larger_than_the_limit_is_refused_unread(tmp_path):
    padding = "#" * SIDE_FILE_MAX_BYTES + "\n"
    message = _refusal(_side_file(tmp_path, padding + VALID))
    assert f"larger than {SIDE_FILE_MAX_BYTES} bytes" in message


@pytest.mark.parametrize(
    "text", ["closed_loop: [[A, B]\n", "name_mot: [m\x07]\n"], ids=["syntax", "control-character"]
)
def test_malformed_yaml_is_refused_in_one_line(tmp_path, text):
    assert "not a readable YAML file" in _refusal(_side_file(tmp_path, text))


@pytest.mark.parametrize(
    "loops", ["[[A, B], [B, A]]", "[[A, B], [C, D], [A, B]]"], ids=["reversed", "repeated"]
)
def test_a_loop_listed_twice_is_refused(tmp_path, loops):
    """The same frame pair, in either order, would be taken as two cuts of one joint."""
    text = f"closed_loop: {loops}\nname_mot: [m]\n"
    message = _refusal(_side_file(tmp_path, text))
    assert "closed_loop entries #1 ['A', 'B'] and #" in message
    assert "join the same frames" in message
