"""Closed kinematic chains of any model: strict reading, typed loop closures, assembly, mobility,
inverse dynamics with every joint's reaction, and forward simulation.

This layer knows nothing of the feeding device: it imports only :mod:`feeder.exceptions`,
:mod:`feeder.validation` and :mod:`feeder.inertia` (tests/test_layers.py checks it). Its
subpackages follow the data:

* :mod:`~feeder.chain.model` — the tree, its loop closures (:class:`ClosedChain`,
  :class:`Closure`), its force elements (:class:`Spring`, :class:`Cylinder`,
  :class:`JointSpring`, :class:`Load`) and its base's motion (:class:`BaseMotion`: a slope, a
  ride over terrain, a bump, recoil rocking, a hull table);
* :mod:`~feeder.chain.readers` — model files (URDF, SDF, MJCF), closure side-files (TOML,
  Extended-URDF YAML) and motion tables, read strictly into a :class:`ClosedChain`;
* :mod:`~feeder.chain.kinematics` — the tree's motion and the closure rows at every sample at
  once, the motion of named frames (:func:`frame_motion`), and one pose with its kinematics run
  once (:class:`~feeder.chain.results.ChainPose`);
* :mod:`~feeder.chain.assembly` — closed poses from the open one, the pose check, velocities and
  accelerations (:class:`Partition`, :class:`~feeder.chain.results.PoseCheck`), and
  continuation along a motion (:func:`track`, giving a
  :class:`~feeder.chain.results.Trajectory`);
* :mod:`~feeder.chain.mobility` — degrees of freedom, redundant rows, admissible inputs, idle
  motions, distance to a singular pose;
* :mod:`~feeder.chain.dynamics` — inverse dynamics (actuator loads, closure forces, every joint's
  reaction), forward runs with error control (:func:`simulate`), and hybrid runs whose actuated
  joints follow a motion while the freedoms they leave free are integrated
  (:func:`hybrid_run`).

The names below are the workflow for any mechanism: read it (:func:`read_spec`,
:func:`load_mechanism`, or :func:`load_closed_chain` for a URDF and closures given in code), its
closures and base motion, assemble and track it (:class:`Partition`, :func:`track`), start it
with given joint rates (:func:`initial_rates`: closed, projected when they contradict), count its
freedoms (:func:`mobility`), and ask what it takes (:class:`ChainDynamics`,
:func:`inverse_dynamics`, :func:`simulate` and its default :data:`BAUMGARTE_RATE`,
:func:`hybrid_run`, the force elements). Two public groupings hold the rest:

* :mod:`feeder.chain.readers` — the individual readers and their records (``read_urdf``,
  ``build_model``, ``read_motion`` → ``MotionTable``, ``read_base``, ``read_force_file``,
  ``MechanismSpec``, …);
* :mod:`feeder.chain.results` — what the workflow returns (``ChainLoads``, ``JointWrench``,
  ``ForwardRun``, ``Trajectory``, ``PoseCheck``, ``MobilityReport``, …), for type annotations.

Tolerances and limits live next to where they are checked (``MAX_GAIN`` in
:mod:`feeder.chain.assembly.partition`, ``POSITION_TOLERANCE`` in
:mod:`feeder.chain.assembly.newton`).

The names below load on first use, so that a command that only reads a model or builds the
device's tree does not import what only tracking (``scipy.linalg``) or forward runs
(``scipy.integrate``) need.
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

# Bound here, not on first use: once the submodule ``mobility`` is imported (by any module),
# the package's attribute ``mobility`` would be that module, and __getattr__ never asked.
from .mobility import mobility

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .assembly.partition import Partition
    from .assembly.rates import initial_rates
    from .assembly.tracking import track
    from .dynamics.forward import simulate
    from .dynamics.forward_equations import BAUMGARTE_RATE
    from .dynamics.hybrid import hybrid_run
    from .dynamics.inverse import ChainDynamics, inverse_dynamics
    from .kinematics.frames import frame_motion
    from .model.base import BaseMotion
    from .model.closure import ClosedChain, Closure
    from .model.forces import Cylinder, ForceElement, JointSpring, Load, Spring, Table
    from .model.hull_table import HullTable
    from .model.profiles import Bump, Recoil, Slope, Terrain
    from .readers.mechanism import load_mechanism, read_spec
    from .readers.urdf import load_closed_chain

_SOURCES = {
    "BAUMGARTE_RATE": ".dynamics.forward_equations",
    "BaseMotion": ".model.base",
    "Bump": ".model.profiles",
    "ChainDynamics": ".dynamics.inverse",
    "ClosedChain": ".model.closure",
    "Closure": ".model.closure",
    "Cylinder": ".model.forces",
    "ForceElement": ".model.forces",
    "HullTable": ".model.hull_table",
    "JointSpring": ".model.forces",
    "Load": ".model.forces",
    "Partition": ".assembly.partition",
    "Recoil": ".model.profiles",
    "Slope": ".model.profiles",
    "Spring": ".model.forces",
    "Table": ".model.forces",
    "Terrain": ".model.profiles",
    "frame_motion": ".kinematics.frames",
    "hybrid_run": ".dynamics.hybrid",
    "initial_rates": ".assembly.rates",
    "inverse_dynamics": ".dynamics.inverse",
    "load_closed_chain": ".readers.urdf",
    "load_mechanism": ".readers.mechanism",
    "read_spec": ".readers.mechanism",
    "simulate": ".dynamics.forward",
    "track": ".assembly.tracking",
}
"""Public name → the module that defines it."""

__all__ = [
    "BAUMGARTE_RATE",
    "BaseMotion",
    "Bump",
    "ChainDynamics",
    "ClosedChain",
    "Closure",
    "Cylinder",
    "ForceElement",
    "HullTable",
    "JointSpring",
    "Load",
    "Partition",
    "Recoil",
    "Slope",
    "Spring",
    "Table",
    "Terrain",
    "frame_motion",
    "hybrid_run",
    "initial_rates",
    "inverse_dynamics",
    "load_closed_chain",
    "load_mechanism",
    "mobility",
    "read_spec",
    "simulate",
    "track",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
