"""Shared fixtures: the reference devices, their cycles at the paper's elevations, a four-bar."""

from __future__ import annotations

import copy
import importlib.metadata
import math
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from feeder import feeding_cycle, load_feeder

ELEVATIONS_DEG = (-4.0, 30.0, 70.0)
REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def feeder():
    return load_feeder("projectile")


@pytest.fixture(scope="session")
def charge_feeder():
    return load_feeder("charge")


@pytest.fixture(scope="session", params=ELEVATIONS_DEG, ids=lambda e: f"eps{e:g}")
def cycle(request, feeder):
    return feeding_cycle(feeder, math.radians(request.param))


@pytest.fixture(scope="session", params=ELEVATIONS_DEG, ids=lambda e: f"eps{e:g}")
def result(request):
    """Full cycle dynamics of the projectile feeder, cached across modules."""
    from .dynamics.cases import cycle_result

    return cycle_result(request.param)


@pytest.fixture(scope="session")
def dyn():
    """The projectile feeder's dynamics models (with and without payload), cached."""
    from .dynamics.cases import device_dynamics

    return device_dynamics()


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


def robots_dir() -> Path:
    share = importlib.metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share")
    return Path(share) / "example-robot-data" / "robots"


def constrained_data(chain):
    """A pinocchio.Data of the chain's model and its constraints' datas, initialised for
    ``pin.constraintDynamics`` with the chain's own constraint models: the bare Pinocchio
    reference the tests compare feeder's runs with."""
    import pinocchio as pin

    data = chain.model.createData()
    datas = pin.StdVec_RigidConstraintData()
    for constraint in chain.constraint_models:
        datas.append(constraint.createData())
    pin.initConstraintDynamics(chain.model, data, chain.constraint_models, datas)
    return data, datas


def four_bar_file(tmp_path: Path, extra: str, mechanism: str = "") -> Path:
    """examples/four_bar's mechanism file written to ``tmp_path`` with the model's absolute path,
    ``mechanism`` lines added to its [mechanism] table and ``extra`` text (tables) at its end."""
    folder = REPO / "examples" / "four_bar"
    text = (folder / "closures.toml").read_text(encoding="utf-8")
    model = (folder / "four_bar.urdf").as_posix()
    lines = f'urdf = "{model}"' + (f"\n{mechanism}" if mechanism else "")
    text = text.replace('urdf = "four_bar.urdf"', lines)
    path = tmp_path / "closures.toml"
    path.write_text(text + "\n" + extra, encoding="utf-8")
    return path


FOURBAR_CRANK, FOURBAR_COUPLER, FOURBAR_ROCKER, FOURBAR_GROUND = 0.1, 0.2, 0.2, 0.22
"""Four-bar lengths [m]: example-robot-data's double pendulum gives the crank (link1, 0.1 m
between its joints) and the coupler (link2); a copy of link2 is added as the rocker, and its tip
is pinned to a ground point; Grashof crank-rocker (0.1 + 0.22 < 0.2 + 0.2)."""


@pytest.fixture(scope="session")
def fourbar_urdf(tmp_path_factory) -> Path:
    """The double pendulum with a rocker appended, its tip and a ground point as closure frames.

    The source URDF's revolute limits are [0, 0] (meaning "not set"): they are widened to ±2π.
    """
    source = robots_dir() / "double_pendulum_description" / "urdf" / "double_pendulum.urdf"
    robot = etree.parse(str(source)).getroot()
    for limit in robot.iter("limit"):
        limit.set("lower", str(-2 * math.pi))
        limit.set("upper", str(2 * math.pi))
    link2 = robot.find("link[@name='link2']")
    rocker = copy.deepcopy(link2)
    rocker.set("name", "rocker")
    for tag in ("visual", "collision"):
        for element in rocker.findall(tag):
            rocker.remove(element)
    robot.append(rocker)
    joint2 = robot.find("joint[@name='joint2']")
    joint3 = copy.deepcopy(joint2)
    joint3.set("name", "joint3")
    joint3.find("origin").set("xyz", f"0 0 {FOURBAR_COUPLER}")
    joint3.find("parent").set("link", "link2")
    joint3.find("child").set("link", "rocker")
    robot.append(joint3)
    tip = etree.SubElement(robot, "link", name="rocker_tip")
    joint = etree.SubElement(robot, "joint", name="rocker_tip_joint", type="fixed")
    etree.SubElement(joint, "origin", xyz=f"0 0 {FOURBAR_ROCKER}", rpy="0 0 0")
    etree.SubElement(joint, "parent", link="rocker")
    etree.SubElement(joint, "child", link=tip.get("name"))
    # Joint 1 is at (0.0060872, 0, 0.035) in base_link; joint 2 at x + 0.023 in link 1.
    plane_x = 0.0060872 + 0.023
    etree.SubElement(robot, "link", name="ground_pin")
    joint = etree.SubElement(robot, "joint", name="ground_pin_joint", type="fixed")
    etree.SubElement(joint, "origin", xyz=f"{plane_x} {FOURBAR_GROUND} 0.035", rpy="0 0 0")
    etree.SubElement(joint, "parent", link="base_link")
    etree.SubElement(joint, "child", link="ground_pin")
    path = tmp_path_factory.mktemp("fourbar") / "fourbar.urdf"
    path.write_bytes(etree.tostring(robot, xml_declaration=True, encoding="utf-8"))
    return path


@pytest.fixture
def dask_scheduler():
    """The address of a Dask LocalCluster (two worker processes, one thread each, on
    127.0.0.1, no dashboard) for the test's duration; skips without the cluster extra."""
    distributed = pytest.importorskip(
        "distributed", reason="dask.distributed (the cluster extra) not installed"
    )
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        yield cluster.scheduler_address
