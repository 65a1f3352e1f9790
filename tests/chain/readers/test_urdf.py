"""Strict URDF loading: every bad input gets a clear feeder exception."""

from __future__ import annotations

import pinocchio as pin
import pytest
import yourdfpy

from feeder.chain import load_closed_chain
from feeder.chain.readers.urdf import build_model, mesh_path, read_urdf
from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.urdf_writer import urdf_string
from feeder.exceptions import ClosureFrameError, InertiaError, ModelFolderError, UrdfError

from ...conftest import REPO

ROUND_OFF = 1e-12
"""Relative: the same rotation by 0.3 rad about z built twice, once from a normalised axis."""


@pytest.fixture
def urdf_text():
    return urdf_string(PROJECTILE_FEEDER)


def write(tmp_path, text, name="robot.urdf"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_missing_file(tmp_path):
    with pytest.raises(UrdfError, match="not found"):
        load_closed_chain(tmp_path / "nope.urdf", [("piston_pin", "arm_pin")])


def test_malformed_xml_is_refused_although_yourdfpy_recovers(tmp_path, urdf_text):
    broken = urdf_text.replace("</robot>", "").replace('<link name="arm">', '<link name="arm">\n<')
    path = write(tmp_path, broken)
    # yourdfpy silently recovers a partial model: this is why feeder parses strictly itself.
    yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
    with pytest.raises(UrdfError, match="malformed XML"):
        load_closed_chain(path, [("piston_pin", "arm_pin")])


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            '<parent link="arm" />\n    <child link="forearm" />',
            '<parent link="arm" />\n    <child link="forarm" />',
            "unknown link",
        ),
        ('type="revolute"', 'type="hinge"', "unknown type"),
        ('<child link="arm" />', '<child link="cylinder" />', "two parent joints"),
    ],
)
def test_broken_trees(tmp_path, urdf_text, old, new, message):
    assert old in urdf_text
    with pytest.raises(UrdfError, match=message):
        load_closed_chain(write(tmp_path, urdf_text.replace(old, new, 1)), [])


@pytest.mark.parametrize(
    "old, new, link, message",
    [
        ('<mass value="18.663" />', '<mass value="-18.663" />', "arm", "negative"),
        ('<mass value="18.663" />', '<mass value="nan" />', "arm", "finite"),
        ('<mass value="18.663" />', '<mass value="heavy" />', "arm", "unparsable"),
        ('iyy="0.005036"', 'iyy="0.05036"', "arm", "triangle"),
        ('iyy="0.01054"', 'iyy="-0.01054"', "piston", "positive semi-definite"),
    ],
)
def test_non_physical_inertia_names_the_link(tmp_path, urdf_text, old, new, link, message):
    assert old in urdf_text
    with pytest.raises(InertiaError, match=message) as info:
        load_closed_chain(write(tmp_path, urdf_text.replace(old, new)), [])
    assert info.value.link == link


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('<origin xyz="0.18 0.0 0.0"', '<origin xyz="nan 0.0 0.0"', "link 'cylinder'"),
        ('<origin xyz="0.18 0.0 0.0"', '<origin xyz="0.18 0.0"', "3 finite numbers"),
        ('<axis xyz="0.0 0.0 1.0" />', '<axis xyz="0.0 0.0 inf" />', "axis"),
        ('lower="0.2304"', 'lower="low"', "limit"),
        ('lower="0.2304"', 'lower="0.6"', "lower=0.6 is above upper=0.5283: swap them"),
    ],
)
def test_non_finite_origins_axes_and_limits(tmp_path, urdf_text, old, new, message):
    """Pinocchio would zero the cylinder's mass for a NaN inertial origin, without a word."""
    assert old in urdf_text
    with pytest.raises(UrdfError, match=message):
        load_closed_chain(write(tmp_path, urdf_text.replace(old, new, 1)), [])


def test_wrong_root_element(tmp_path):
    with pytest.raises(UrdfError, match="root element"):
        load_closed_chain(write(tmp_path, "<sdf><model/></sdf>"), [])


def test_urdf_without_closure_frames(tmp_path):
    path = REPO / "urdf" / "projectile_feeder.urdf"
    with pytest.raises(ClosureFrameError, match="rod_eye"):
        load_closed_chain(path, [("rod_eye", "arm_pin")])


def test_shipped_file_loads(feeder):
    chain = load_closed_chain(
        REPO / "urdf" / "projectile_feeder.urdf", [("piston_pin", "arm_pin")]
    )
    assert chain.model.nq == feeder.model.nq == 4
    assert chain.nc == 3


def test_text_is_checked_like_a_file(urdf_text):
    """build_model checks URDF text as strictly as a file and names the given source."""
    model = build_model(urdf_text, "<generated>")
    assert model.nq == 4
    broken = urdf_text.replace('<mass value="18.663" />', '<mass value="nan" />')
    with pytest.raises(InertiaError, match="finite"):
        build_model(broken, "<generated>")
    with pytest.raises(UrdfError, match="<generated>.*malformed XML"):
        build_model(urdf_text.replace("</robot>", ""), "<generated>")


def test_read_urdf_refuses_a_folder(tmp_path):
    with pytest.raises(UrdfError, match="is a folder, not a file"):
        read_urdf(tmp_path)


def test_doctype_with_an_entity_is_refused(tmp_path, urdf_text):
    """lxml expands ``&m;`` for the checks while Pinocchio's parser drops the inertia it cannot
    read: the 43.5 kg payload would vanish from the model without a word."""
    assert '<mass value="43.5" />' in urdf_text
    hostile = urdf_text.replace(
        "<robot ", '<!DOCTYPE robot [<!ENTITY m "43.5">]>\n<robot ', 1
    ).replace('<mass value="43.5" />', '<mass value="&m;" />')
    # Control: Pinocchio itself builds this file and loses the payload's mass.
    model = pin.buildModelFromXML(hostile)
    assert model.inertias[model.getJointId("forearm_joint")].mass < (
        PROJECTILE_FEEDER.forearm.mass + PROJECTILE_FEEDER.payload.mass / 2
    )
    with pytest.raises(UrdfError, match="document type declaration"):
        load_closed_chain(write(tmp_path, hostile), [])


@pytest.mark.parametrize(
    "declaration",
    ["<!DOCTYPE robot>", '<!DOCTYPE robot SYSTEM "robot.dtd">', "<!DOCTYPE robot [ ]>"],
)
def test_any_doctype_is_refused(urdf_text, declaration):
    with pytest.raises(UrdfError, match="document type declaration"):
        build_model(urdf_text.replace("<robot ", f"{declaration}\n<robot ", 1))


@pytest.mark.parametrize("axis", ["0.0 0.0 0.0", "0 0 1e-300", "-0.0 0 0"])
def test_zero_joint_axis_is_refused(tmp_path, urdf_text, axis):
    """Pinocchio turns a zero axis into a joint motion whose "rotation" has det ≠ 1."""
    old = '<axis xyz="0.0 0.0 1.0" />'
    assert old in urdf_text
    with pytest.raises(UrdfError, match="cylinder_joint.*not a direction"):
        load_closed_chain(write(tmp_path, urdf_text.replace(old, f'<axis xyz="{axis}" />', 1)), [])


def test_zero_axis_of_a_fixed_joint_is_accepted(urdf_text):
    """Exporters write ``0 0 0`` on fixed joints, whose axis nobody uses."""
    fixed = '<joint name="projectile_joint" type="fixed">'
    assert fixed in urdf_text
    text = urdf_text.replace(fixed, fixed + '\n    <axis xyz="0 0 0" />', 1)
    assert build_model(text).nq == 4


def test_a_non_unit_axis_is_a_direction(urdf_text):
    """Pinocchio normalises the axis: ``0 0 2`` is accepted and is the same joint as ``0 0 1``."""
    text = urdf_text.replace('<axis xyz="0.0 0.0 1.0" />', '<axis xyz="0.0 0.0 2.0" />', 1)
    model, reference = build_model(text), build_model(urdf_text)
    q = pin.neutral(model) + 0.3
    data, reference_data = model.createData(), reference.createData()
    pin.forwardKinematics(model, data, q)
    pin.forwardKinematics(reference, reference_data, q)
    joint = model.getJointId("cylinder_joint")
    assert data.oMi[joint].isApprox(reference_data.oMi[joint], ROUND_OFF)


@pytest.mark.parametrize(
    "uri",
    [
        "package:///../secret.stl",
        "package://model/../secret.stl",
        "../secret.stl",
        "file://{outside}/secret.stl",
        "link_out.stl",
        "linked_folder/secret.stl",
    ],
)
def test_a_mesh_path_outside_the_model_folder_is_refused(tmp_path, uri):
    """``..``, an absolute path and symbolic links (to a file, to a folder) that lead out of the
    URDF's folder: refused, naming the URI, although the file exists."""
    folder = tmp_path / "model"
    folder.mkdir()
    (tmp_path / "secret.stl").write_text("solid secret\nendsolid secret\n")
    (folder / "link_out.stl").symlink_to(tmp_path / "secret.stl")
    (folder / "linked_folder").symlink_to(tmp_path, target_is_directory=True)
    uri = uri.format(outside=tmp_path)
    with pytest.raises(ModelFolderError) as info:
        mesh_path(uri, folder / "robot.urdf")
    assert str(info.value).startswith(f"mesh {uri!r} of {folder / 'robot.urdf'} lies outside the")


def test_a_mesh_path_inside_the_model_folder_is_resolved(tmp_path):
    """Subfolders, ``..`` that stay inside, ``file://`` to a file inside, a link inside."""
    (tmp_path / "meshes").mkdir()
    mesh = tmp_path / "meshes" / "crank.stl"
    mesh.write_text("solid crank\nendsolid crank\n")
    (tmp_path / "link.stl").symlink_to(mesh)
    urdf = tmp_path / "robot.urdf"
    for uri in ("meshes/crank.stl", "package://pkg/meshes/../meshes/crank.stl", f"file://{mesh}"):
        assert mesh_path(uri, urdf) == mesh.resolve()
    assert mesh_path("link.stl", urdf) == mesh.resolve()
    with pytest.raises(UrdfError, match="not found"):
        mesh_path("meshes/other.stl", urdf)


def test_a_mesh_path_through_a_loop_of_links_is_refused(tmp_path):
    (tmp_path / "a.stl").symlink_to(tmp_path / "b.stl")
    (tmp_path / "b.stl").symlink_to(tmp_path / "a.stl")
    with pytest.raises(UrdfError, match=r"mesh 'a.stl' of .* cannot be resolved"):
        mesh_path("a.stl", tmp_path / "robot.urdf")
