"""Closed kinematic chains of any model: strict reading, typed loop closures, assembly, mobility,
inverse dynamics with every joint's reaction, and forward simulation.

This layer knows nothing of the feeding device: it imports only :mod:`feeder.exceptions` and
:mod:`feeder.validation` (tests/test_layers.py checks it). Its subpackages follow the data:

* :mod:`~feeder.chain.model` — the tree, its loop closures (:class:`ClosedChain`,
  :class:`Closure`), its force elements (:class:`Spring`, :class:`Cylinder`,
  :class:`JointSpring`, :class:`Load`) and its base's motion (:class:`BaseMotion`: a slope, a
  ride over terrain, a bump, recoil rocking, a hull table);
* :mod:`~feeder.chain.readers` — model files (URDF, SDF, MJCF), closure side-files (TOML,
  Extended-URDF YAML) and motion tables, read strictly into a :class:`ClosedChain`;
* :mod:`~feeder.chain.kinematics` — the tree's motion and the closure rows at every sample at
  once, the motion of named frames (:func:`frame_motion`), and one pose with its kinematics run
  once (:class:`ChainPose`);
* :mod:`~feeder.chain.assembly` — closed poses from the open one, the pose check, velocities and
  accelerations (:class:`Partition`, :class:`PoseCheck`), and continuation along a motion
  (:func:`track`, giving a :class:`Trajectory`);
* :mod:`~feeder.chain.mobility` — degrees of freedom, redundant rows, admissible inputs, idle
  motions, distance to a singular pose;
* :mod:`~feeder.chain.dynamics` — inverse dynamics (actuator loads, closure forces, every joint's
  reaction) and forward runs with error control (:func:`simulate`).
"""

from .assembly.check import PoseCheck
from .assembly.partition import MAX_GAIN, POSITION_TOLERANCE, Partition
from .assembly.tracking import track
from .assembly.trajectory import Trajectory
from .dynamics.derivatives import mass_matrix_derivative
from .dynamics.forward import simulate
from .dynamics.forward_equations import IntegrationError
from .dynamics.forward_run import ForwardRun
from .dynamics.inverse import ChainDynamics, ChainLoads, inverse_dynamics
from .dynamics.reactions import ClosureWrench, JointWrench, MountWrench
from .kinematics.frames import FrameMotion, frame_motion
from .kinematics.pose import ChainPose
from .mobility import MobilityReport, mobility
from .model.base import BaseMotion, BaseState
from .model.closure import ClosedChain, Closure
from .model.forces import Cylinder, ForceElement, JointSpring, Load, Spring, Table
from .model.hull_table import HullTable
from .model.profiles import Bump, Recoil, Slope, Terrain
from .readers.base_motion import parse_profile, read_base, read_hull_table
from .readers.forces import read_force_file, read_table
from .readers.inertia import check_inertia
from .readers.mechanism import load_mechanism, read_spec
from .readers.motion_table import MotionTable, read_motion
from .readers.pose import read_pose
from .readers.spec import MechanismSpec
from .readers.urdf import build_model, check_urdf, load_closed_chain, mesh_path, read_urdf

__all__ = [
    "MAX_GAIN",
    "POSITION_TOLERANCE",
    "BaseMotion",
    "BaseState",
    "Bump",
    "ChainDynamics",
    "ChainPose",
    "ChainLoads",
    "ClosedChain",
    "Closure",
    "ClosureWrench",
    "Cylinder",
    "ForceElement",
    "ForwardRun",
    "FrameMotion",
    "HullTable",
    "IntegrationError",
    "JointSpring",
    "JointWrench",
    "Load",
    "MechanismSpec",
    "MobilityReport",
    "MotionTable",
    "MountWrench",
    "Partition",
    "PoseCheck",
    "Recoil",
    "Slope",
    "Spring",
    "Table",
    "Terrain",
    "Trajectory",
    "build_model",
    "check_inertia",
    "check_urdf",
    "frame_motion",
    "inverse_dynamics",
    "load_closed_chain",
    "load_mechanism",
    "mass_matrix_derivative",
    "mesh_path",
    "mobility",
    "parse_profile",
    "read_base",
    "read_force_file",
    "read_hull_table",
    "read_motion",
    "read_pose",
    "read_spec",
    "read_table",
    "read_urdf",
    "simulate",
    "track",
]
