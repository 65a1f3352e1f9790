"""Real CAD exports (Onshape, Extended-URDF form; examples/cad, from Gepetto's
example-parallel-robots): each loads from its YAML as shipped, mounts from its open pose, reports
its mobility and idle motions, follows ±0.1 rad sinusoids of its motors, and its motor loads drive
Pinocchio's own ``constraintDynamics`` to the same accelerations.
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import (
    ChainDynamics,
    Partition,
    inverse_dynamics,
    load_mechanism,
    mobility,
    track,
)
from feeder.chain.readers.mechanism import read_spec
from feeder.exceptions import FeederWarning, InputError, UnreachablePoseError

from ..conftest import REPO, constrained_data

CAD = REPO / "examples" / "cad"

IDLE = {"5bar_linkage": 1, "robot_delta": 3, "cassie_like": 2, "battobot_6d": 0}
"""Idle motions with the motors locked, counted by hand from the drawings: the 5-bar's two
coaxial hinges at its cut turn together; the delta's three rods and Cassie's two rods each spin
about their axis between two balls; the biped's balls and universal joints (its YAML overrides)
leave none."""

LOOP_ROUND_OFF = 1e-12
"""[m] Closure residual after the mount: Newton stops at 1e-13 m."""

DYNAMICS = 1e-9
"""Relative agreement of the accelerations that constraintDynamics gives for the computed motor
loads with the prescribed ones (outside idle motions; relative to the largest): both solve the
same KKT system, with condition numbers up to ~1e5 here (light frame links beside kilograms):
1e5 × 1e-16 ≈ 1e-11 (measured ≤ 2e-11)."""


def load(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)  # the 5-bar's 654-tonne sphere
        spec = read_spec(CAD / name / "robot.yaml")
        return spec, load_mechanism(spec)


@pytest.fixture(scope="module", params=list(IDLE))
def robot(request):
    spec, chain = load(request.param)
    partition = Partition(chain, spec.independent)
    assembled = partition.mount(pin.neutral(chain.model))
    return request.param, spec, chain, partition, assembled


def sinusoids(chain, partition, spec, assembled, samples=101):
    """±0.1 rad sinusoids of every motor over 1 s about the assembled pose (moved inside the
    joint limits where it is closer than 0.1 rad to one), with exact rates."""
    model = chain.model
    x0 = partition.independent_values(assembled)
    index = [model.joints[model.getJointId(name)].idx_q for name in spec.independent]
    low, high = model.lowerPositionLimit[index], model.upperPositionLimit[index]
    centre = np.where((low == 0.0) & (high == 0.0), x0, np.clip(x0, low + 0.1, high - 0.1))
    t = np.linspace(0.0, 1.0, samples)[:, None]
    w = 2.0 * np.pi
    ones = np.ones(len(spec.independent))
    return (
        centre + 0.1 * np.sin(w * t) * ones,
        0.1 * w * np.cos(w * t) * ones,
        -0.1 * w**2 * np.sin(w * t) * ones,
    )


def test_mount_closes_every_loop_from_the_open_pose(robot):
    name, _, chain, _, assembled = robot
    assert np.abs(chain.residual(pin.neutral(chain.model))).max() > 1e-3  # open as exported
    assert np.abs(chain.residual(assembled)).max() <= LOOP_ROUND_OFF


def test_mobility_names_the_idle_motions_and_admits_the_motors(robot):
    name, spec, chain, partition, assembled = robot
    report = mobility(chain, assembled, spec.independent)
    assert report.determined is None, report.determined
    assert len(report.idle) == IDLE[name]
    assert report.mobility == len(spec.independent) + IDLE[name]
    for joints in report.idle:  # each idle motion moves joints of one rod or one hinge pair
        assert 1 <= len(joints) <= 2
    assert report.admissible, "no admissible set found"
    text = report.text()
    assert ("partial list" in text) == (not report.complete)
    assert f"{IDLE[name]} idle motion" in text if IDLE[name] else "no idle motion" in text


def test_motor_loads_drive_constraint_dynamics_to_the_motion(robot):
    name, spec, chain, partition, assembled = robot
    model = chain.model
    x, dx, ddx = sinusoids(chain, partition, spec, assembled)
    motion = track(partition, assembled, x, dx, ddx)
    q, v, a = motion.q, motion.v, motion.a
    np.testing.assert_array_equal(
        q[:, [model.joints[model.getJointId(n)].idx_q for n in spec.independent]], x
    )
    loads = inverse_dynamics(ChainDynamics(chain, spec.actuated), q, v, a)
    assert loads.idle_motions == IDLE[name]
    data, datas = constrained_data(chain)
    columns = [chain.joint_slice(n).start for n in spec.actuated]
    # A small proximal μ: the 6-D welds of planar loops have redundant rows (μ = 0 gives NaN).
    settings = pin.ProximalSettings(1e-14, 1e-10, 1000)
    actuated = Partition(chain, spec.actuated)
    for k in range(0, q.shape[0], 10):
        tau = np.zeros(model.nv)
        tau[columns] = [loads.actuators[n][k] for n in spec.actuated]
        ddq = pin.constraintDynamics(
            model, data, q[k], v[k], tau, chain.constraint_models, datas, settings
        )
        error = ddq - loads.accelerations[k]
        idle = actuated.idle_motions(q[k])
        outside = error - idle.T @ (idle @ error)
        scale = np.abs(loads.accelerations[k]).max()
        assert np.abs(outside).max() <= DYNAMICS * scale, (name, k)
        np.testing.assert_allclose(loads.accelerations[k][columns], a[k][columns], rtol=0, atol=0)


def test_yaml_joint_types_replace_the_urdf_joints():
    _, chain = load("battobot_6d")
    kinds = {
        chain.model.names[j]: chain.model.joints[j].shortname()
        for j in range(1, chain.model.njoints)
    }
    assert kinds["left_spherical_ankle_1"] == "JointModelUniversal"
    assert kinds["right_spherical_foot_2"] == "JointModelSpherical"
    assert kinds["hipz_left"] == "JointModelRZ"


def test_a_toml_side_file_replaces_joints_as_the_yaml_does(tmp_path):
    """The same export written as URDF + TOML, its ball and universal joints under
    ``[mechanism] joint_types``: the same model, joint by joint."""
    yaml_spec = read_spec(CAD / "battobot_6d" / "robot.yaml")
    loops = "".join(
        f'[[closure]]\nframes = ["{c.frame_a}", "{c.frame_b}"]\ntype = "{c.kind}"\n'
        for c in yaml_spec.closures
    )
    types = ", ".join(f'{name} = "{kind}"' for name, kind in yaml_spec.joint_types.items())
    toml = tmp_path / "robot.toml"
    toml.write_text(
        f'[mechanism]\nurdf = "{CAD / "battobot_6d" / "robot.urdf"}"\n'
        f"actuated = {list(yaml_spec.actuated)}\nindependent = {list(yaml_spec.independent)}\n"
        f"joint_types = {{{types}}}\n{loops}".replace("'", '"'),
        encoding="utf-8",
    )
    toml_spec = read_spec(toml)
    assert toml_spec.joint_types == yaml_spec.joint_types and toml_spec.joint_types
    models = [load_mechanism(spec).model for spec in (yaml_spec, toml_spec)]
    for model in models[1:]:
        assert [j.shortname() for j in model.joints] == [j.shortname() for j in models[0].joints]
        assert list(model.names) == list(models[0].names)


@pytest.mark.parametrize(
    "types, match",
    [
        ('{hipz_left = "BALL"}', "joint_types.hipz_left: unknown joint type 'BALL'"),
        ('"SPHERICAL"', "joint_types must be a table"),
    ],
)
def test_bad_toml_joint_types_are_refused(tmp_path, types, match):
    toml = tmp_path / "robot.toml"
    toml.write_text(
        f'[mechanism]\nurdf = "{CAD / "battobot_6d" / "robot.urdf"}"\nactuated = ["a"]\n'
        f'independent = ["a"]\njoint_types = {types}\n',
        encoding="utf-8",
    )
    with pytest.raises(InputError, match=match):
        read_spec(toml)


def test_the_implausible_sphere_is_named():
    with pytest.warns(FeederWarning, match="weighs 654498 kg"):
        load_mechanism(read_spec(CAD / "5bar_linkage" / "robot.yaml"))


@pytest.mark.parametrize(
    "text, match",
    [
        ("closed_loop: [['a', 'b']]\ntype: ['2d']\nname_mot: ['mot1']\n", "'2d'"),
        ("closed_loop: [['a']]\nname_mot: ['mot1']\n", "pairs of frame names"),
        ("closed_loop: [['a', 'b']]\ntype: ['6d', '3d']\nname_mot: ['mot1']\n", "one type per"),
        ("closed_loop: [['a', 'b']]\n", "name_mot"),
        ("closed_loop: [['a', 'b']]\nname_mot: [mot1, mot1]\n", "distinct"),
        (
            "closed_loop: [['a', 'b']]\nname_mot: [mot1]\njoint_name: [j]\njoint_type: [BALL]\n",
            "unknown joint type 'BALL'",
        ),
        (
            "closed_loop: [['a', 'b']]\nname_mot: [mot1]\njoint_name: [j, k]\n"
            "joint_type: [FIXED]\n",
            "one length",
        ),
        ("[unclosed", "not a readable YAML"),
        ("- a list\n", "mapping"),
    ],
)
def test_bad_side_files_are_refused_with_the_key(tmp_path, text, match):
    (tmp_path / "robot.urdf").write_text((CAD / "5bar_linkage" / "robot.urdf").read_text())
    (tmp_path / "robot.yaml").write_text(text)
    with pytest.raises(InputError, match=match):
        read_spec(tmp_path / "robot.yaml")


@pytest.mark.filterwarnings("ignore::feeder.exceptions.FeederWarning")
def test_an_override_of_an_unknown_joint_is_refused(tmp_path):
    (tmp_path / "robot.urdf").write_text((CAD / "5bar_linkage" / "robot.urdf").read_text())
    (tmp_path / "robot.yaml").write_text(
        "closed_loop: [['closedloop1_A', 'closedloop1_B']]\nname_mot: [mot1, mot2]\n"
        "joint_name: [no_such_joint]\njoint_type: [SPHERICAL]\n"
    )
    with pytest.raises(InputError, match="'no_such_joint' is not a joint"):
        load_mechanism(read_spec(tmp_path / "robot.yaml"))


@pytest.mark.filterwarnings("ignore::feeder.exceptions.FeederWarning")
def test_an_override_of_a_misspelt_joint_names_the_nearest(tmp_path):
    """The collection's disney_robot names 'left_spherical_free_foot' in its side-file while its
    URDF spells the joint 'left_sĥerical_free_foot': the refusal points at the spelling."""
    text = (CAD / "5bar_linkage" / "robot.urdf").read_text()
    assert text.count('<joint name="free1"') == 1
    (tmp_path / "robot.urdf").write_text(
        text.replace('<joint name="free1"', '<joint name="frĥe1"')
    )
    (tmp_path / "robot.yaml").write_text(
        "closed_loop: [['closedloop1_A', 'closedloop1_B']]\nname_mot: [mot1, mot2]\n"
        "joint_name: [free1]\njoint_type: [SPHERICAL]\n"
    )
    with pytest.raises(
        InputError, match="'free1' is not a joint of the model; did you mean 'frĥe1'"
    ):
        load_mechanism(read_spec(tmp_path / "robot.yaml"))


def test_a_loop_that_cannot_close_is_named_with_its_gap(tmp_path):
    """The 5-bar's cut frames paired with the base frame instead: the mount names the loop."""
    (tmp_path / "robot.urdf").write_text((CAD / "5bar_linkage" / "robot.urdf").read_text())
    (tmp_path / "robot.yaml").write_text(
        "closed_loop: [['closedloop1_A', 'closedloop1_B'], ['closedloop1_A', 'universe']]\n"
        "type: ['6d', '3d']\nname_mot: [mot1, mot2]\n"
    )
    spec, chain = None, None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)
        spec = read_spec(tmp_path / "robot.yaml")
        chain = load_mechanism(spec)
    with pytest.raises(
        UnreachablePoseError, match=r"loop 'closedloop1_A-universe': gap [0-9.]+ m"
    ) as refusal:
        Partition(chain, spec.independent).mount(pin.neutral(chain.model))
    assert "A loop that does not close even alone has frames its joints cannot" in str(
        refusal.value
    )  # what to do: the collection's kangaroo legs have loops 5 mm and 4 cm short alone


def test_motion_columns_land_on_the_joints_they_name():
    """Motors named out of the model's joint order: each column goes to its own joint (it went
    to the other one, silently, before)."""
    spec, chain = load("5bar_linkage")
    model = chain.model
    forward = Partition(chain, ["mot1", "mot2"])
    backward = Partition(chain, ["mot2", "mot1"])
    assembled = forward.mount(pin.neutral(model))
    x1, x2 = forward.independent_values(assembled)
    x = np.array([[x1, x2], [x1 + 0.05, x2 - 0.02]])
    q_forward = track(forward, assembled, x).q
    q_backward = track(backward, assembled, x[:, ::-1]).q
    np.testing.assert_allclose(q_backward, q_forward, atol=1e-12)
    mot1 = model.joints[model.getJointId("mot1")].idx_q
    mot2 = model.joints[model.getJointId("mot2")].idx_q
    assert (q_backward[1, mot1], q_backward[1, mot2]) == (x1 + 0.05, x2 - 0.02)


def test_a_forward_run_with_ball_and_universal_joints_keeps_its_energy_balance():
    """The biped (quaternion balls, universal joints) run forward from rest under constant motor
    torques for 20 ms: configurations stay on their Lie groups (unit quaternions), the loops stay
    closed, and the motors' work is the change of energy."""
    from feeder.chain import simulate

    spec, chain = load("battobot_6d")
    partition = Partition(chain, spec.independent)
    q0 = partition.mount(pin.neutral(chain.model))
    dyn = ChainDynamics(chain, spec.actuated)
    torque = np.linspace(-0.01, 0.01, len(spec.actuated))  # [N·m]: links of 17–300 g
    run = simulate(dyn, np.linspace(0.0, 0.02, 21), q0, np.zeros(48), lambda t, q, v: torque)
    model = chain.model
    for j in range(1, model.njoints):
        if model.joints[j].shortname() == "JointModelSpherical":
            quaternions = run.q[:, model.joints[j].idx_q : model.joints[j].idx_q + 4]
            np.testing.assert_allclose(np.linalg.norm(quaternions, axis=1), 1.0, atol=1e-12)
    # DOP853 at the default tolerances (rtol 1e-8, atol 1e-10) on a motion reaching 2.6 rad/s:
    # drift and energy error measured 1.9e-13 m and 1.2e-12 J; the bounds leave room and are far
    # below the motion's energy change (9e-5 J).
    assert run.drift() <= 1e-8
    assert run.energy_error() <= 1e-8
    # the motors' torques come back from the run's inverse dynamics
    applied = np.array([run.loads.actuators[name] for name in spec.actuated]).T
    np.testing.assert_allclose(applied, np.tile(torque, (21, 1)), atol=1e-9)
    assert abs(run.energy[-1] - run.energy[0]) > 1e-5


def test_a_continuous_crank_is_prescribed_by_its_angle(tmp_path):
    """The four-bar's crank written as a URDF ``continuous`` joint (two coordinates, cos and sin)
    follows the same motion table and needs the same torque as the revolute one."""
    from feeder.study.analyze import analyze

    folder = REPO / "examples" / "four_bar"
    text = (folder / "four_bar.urdf").read_text()
    start = text.index('<joint name="crank_joint" type="revolute">')
    text = text[:start] + text[start:].replace('type="revolute"', 'type="continuous"', 1)
    (tmp_path / "four_bar.urdf").write_text(text)
    (tmp_path / "closures.toml").write_text((folder / "closures.toml").read_text())
    revolute = analyze(folder / "closures.toml", folder / "motion.csv")
    continuous = analyze(tmp_path / "closures.toml", folder / "motion.csv")
    assert continuous.chain.model.nq == 4 and continuous.chain.model.nv == 3
    torque = revolute.loads.actuators["crank_joint"]
    np.testing.assert_allclose(
        continuous.loads.actuators["crank_joint"], torque, atol=1e-9 * np.abs(torque).max()
    )
    angle = continuous.columns()["q_crank_joint"]
    wrapped = np.pi - np.mod(np.pi - revolute.columns()["q_crank_joint"], 2.0 * np.pi)
    np.testing.assert_allclose(angle, wrapped, atol=1e-12)


def test_package_mesh_paths_resolve_beside_the_urdf():
    from lxml import etree

    from feeder.chain.readers.urdf import mesh_path
    from feeder.exceptions import UrdfError

    urdf = CAD / "cassie_like" / "robot.urdf"
    uris = {m.get("filename") for m in etree.parse(str(urdf)).getroot().iter("mesh")}
    assert uris and all(uri.startswith("package:///") for uri in uris)
    for uri in uris:
        assert mesh_path(uri, urdf).parent == urdf.parent
    with pytest.raises(UrdfError, match="no_such.stl"):
        mesh_path("package:///no_such.stl", urdf)
