"""Closed kinematic chains of any model: strict reading, typed loop closures, assembly, mobility,
inverse dynamics with every joint's reaction, and forward simulation.

This layer knows nothing of the feeding device: it imports only :mod:`feeder.exceptions` and
:mod:`feeder.validation` (tests/test_layers.py checks it). Data flow:
model file (URDF, MJCF, SDF) and closure side-file (:mod:`~feeder.chain.spec`) →
:class:`ClosedChain` (the tree and its :class:`Closure` s) → :class:`Partition` (assembly,
velocity, acceleration, continuation along a trajectory) and :func:`mobility` (degrees of
freedom, redundant rows, admissible inputs, distance to a singular pose) →
:func:`inverse_dynamics` (actuator loads, closure forces, every joint's reaction) and
:func:`simulate` (forward runs driven by actuator forces).
"""

from .assembly import MAX_GAIN, POSITION_TOLERANCE, Partition
from .closure import ClosedChain, Closure, load_closed_chain
from .derivatives import mass_matrix_derivative
from .forward import ForwardRun, simulate
from .inertia import check_inertia
from .inverse import ChainDynamics, ChainLoads, ClosureWrench, JointWrench, inverse_dynamics
from .mobility import MobilityReport, mobility
from .spec import MechanismSpec, MotionTable, load_mechanism, read_motion, read_spec
from .urdf import build_model, check_urdf, read_urdf

__all__ = [
    "MAX_GAIN",
    "POSITION_TOLERANCE",
    "ChainDynamics",
    "ChainLoads",
    "ClosedChain",
    "Closure",
    "ClosureWrench",
    "ForwardRun",
    "JointWrench",
    "MechanismSpec",
    "MobilityReport",
    "MotionTable",
    "Partition",
    "build_model",
    "check_inertia",
    "check_urdf",
    "inverse_dynamics",
    "load_closed_chain",
    "load_mechanism",
    "mass_matrix_derivative",
    "mobility",
    "read_motion",
    "read_spec",
    "read_urdf",
    "simulate",
]
