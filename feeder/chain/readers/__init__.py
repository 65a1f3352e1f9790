"""Strict readers: model files (URDF, SDF, MJCF), closure side-files (TOML, Extended-URDF YAML)
and motion tables, every number checked before Pinocchio sees it.

The two front doors, :func:`~feeder.chain.read_spec` and :func:`~feeder.chain.load_mechanism`
(and :func:`~feeder.chain.load_closed_chain`), are in :mod:`feeder.chain`; the names below are
the single readers behind them, for a script that needs one piece: the URDF and its model
(:func:`read_urdf`, :func:`build_model`, :func:`check_urdf`, :func:`mesh_path`), the
physical-consistency check of an inertia (:func:`check_inertia`), a pose (:func:`read_pose`), a
motion table (:func:`read_motion` → :class:`MotionTable`), joints under control
(:func:`read_control_file` → :class:`ControlSpec`), a moving base (:func:`read_base`,
:func:`parse_profile`, :func:`read_hull_table`), force elements and their tables
(:func:`read_force_file`, :func:`read_table`), and the record a side-file gives
(:class:`MechanismSpec`).
"""

from ...inertia import check_inertia
from ..model.control import ControlSpec
from .base_motion import parse_profile, read_base, read_hull_table
from .control import read_control_file
from .forces import read_force_file, read_table
from .motion_table import MotionTable, read_motion
from .pose import read_pose
from .spec import MechanismSpec
from .urdf import build_model, check_urdf, mesh_path, read_urdf

__all__ = [
    "ControlSpec",
    "MechanismSpec",
    "MotionTable",
    "build_model",
    "check_inertia",
    "check_urdf",
    "mesh_path",
    "parse_profile",
    "read_base",
    "read_control_file",
    "read_force_file",
    "read_hull_table",
    "read_motion",
    "read_pose",
    "read_table",
    "read_urdf",
]
