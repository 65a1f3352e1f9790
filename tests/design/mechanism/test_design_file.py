"""The design file of a mechanism: what it reads (joint origins, frames, masses, scales) and
what it refuses, each in one line naming the file and the key."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from feeder.design.mechanism.inputs import check_inputs
from feeder.design.mechanism.urdf_edit import Target, edited
from feeder.exceptions import InputError

from .lever import Lever

OBJECTIVE = '\n[objective]\npeak = "tau_cylinder_slide"\n'


def _refusal(tmp_path, design: str) -> str:
    model, closures, motion, path = Lever().write(tmp_path, design)
    with pytest.raises(InputError) as caught:
        check_inputs(model, closures, path, [motion])
    message = str(caught.value)
    assert "\n" not in message and str(path) in message
    return message


def test_infeasible_bounds_are_refused(tmp_path):
    message = _refusal(tmp_path, "[variables]\ncylinder_pivot.x = {lower = 1.6, upper = 0.9}"
                       + OBJECTIVE)  # fmt: skip
    assert "cylinder_pivot.x: lower 1.6 must be below upper 0.9 m" in message


def test_a_start_outside_the_bounds_is_refused(tmp_path):
    design = "[variables]\ncylinder_pivot.x = {lower = 0.9, upper = 1.6, start = 2.0}" + OBJECTIVE
    assert "start 2 is outside [0.9, 1.6] m" in _refusal(tmp_path, design)


def test_a_missing_joint_is_refused_with_its_close_match(tmp_path):
    message = _refusal(tmp_path, "[variables]\ncylinder_pivt.x = {lower = 0.9, upper = 1.6}"
                       + OBJECTIVE)  # fmt: skip
    assert "no joint or frame 'cylinder_pivt'" in message
    assert "did you mean 'cylinder_pivot'?" in message


def test_an_objective_naming_no_load_is_refused_with_the_loads_there_are(tmp_path):
    design = (
        "[variables]\ncylinder_pivot.x = {lower = 0.9, upper = 1.6}\n"
        '[objective]\npeak = "tau_cylinder"\n'
    )
    message = _refusal(tmp_path, design)
    assert "[objective] 'tau_cylinder' names no load of the mechanism" in message
    assert "did you mean 'tau_cylinder_slide'?" in message
    assert "body_hinge_force" in message  # the list of the peaks there are


def test_unknown_keys_are_refused(tmp_path):
    design = "[variables]\ncylinder_pivot.x = {lower = 0.9, upper = 1.6, step = 1}" + OBJECTIVE
    assert "unknown key 'step'" in _refusal(tmp_path, design)
    table = "[variables]\ncylinder_pivot.x = {lower = 0.9, upper = 1.6}\n[objectiv]\npeak = 'x'\n"
    assert "unknown key 'objectiv'" in _refusal(tmp_path, table)


def test_the_editor_moves_an_origin_a_frame_and_scales_a_mass_with_its_inertia():
    lever = Lever()
    targets = [Target("origin", "cylinder_pivot", "y"), Target("origin", "body_pin_joint", "x"),
               Target("mass", "body")]  # fmt: skip
    root = ET.fromstring(edited(lever.urdf(), targets, [-0.5, 0.9, 1000.0]))
    joints = {j.get("name"): j for j in root.findall("joint")}
    assert joints["cylinder_pivot"].find("origin").get("xyz") == "1.0 -0.5 0.0"
    assert joints["body_pin_joint"].find("origin").get("xyz") == "0.9 0.0 0.0"
    inertial = root.find("link[@name='body']/inertial")
    assert float(inertial.find("mass").get("value")) == 1000.0
    assert float(inertial.find("inertia").get("izz")) == lever.inertia * 2.0  # 500 kg → 1000 kg
