"""feeder: rigid-body analysis of the 152 mm SPH M77 ammunition feeding device, on Pinocchio.

Data flow: parameters (:mod:`feeder.parameters`) → URDF (:mod:`feeder.urdf`) → Pinocchio model
with the pin closure (:mod:`feeder.loading`, :mod:`feeder.closure`, :mod:`feeder.device`) →
kinematics (:mod:`feeder.assembly`, :mod:`feeder.kinematics`, :mod:`feeder.cycle`,
:mod:`feeder.workspace`) → dynamics (:mod:`feeder.dynamics`, :mod:`feeder.reactions`,
:mod:`feeder.simulation`, :mod:`feeder.hydraulics`, :mod:`feeder.cycle_dynamics`) → cross-check
with the paper's hand-derived equations (:mod:`feeder.lagrange`, :mod:`feeder.coriolis`,
:mod:`feeder.errata`) → results (:mod:`feeder.study`, :mod:`feeder.results`, :mod:`feeder.plots`,
:mod:`feeder.viewer`).
"""

from .assembly import Partition
from .closure import ClosedChain, load_closed_chain
from .coriolis import kronecker_coriolis
from .cycle import CycleKinematics, CycleSpec, feeding_cycle
from .cycle_dynamics import CycleDynamics, Peak, cycle_dynamics
from .device import CLOSURE, INDEPENDENT_JOINTS, PAPER_JOINTS, Feeder, load_feeder
from .dynamics import ActuatorLoads, FeederDynamics, inverse_dynamics
from .exceptions import (
    ClosureFrameError,
    ElevationError,
    FeederError,
    ForwardDivergenceError,
    InertiaError,
    InputError,
    SingularPoseError,
    UnreachablePoseError,
    UrdfError,
    ViewerPortError,
)
from .hydraulics import CylinderPressures, cylinder_pressures, rack_force
from .kinematics import (
    SINGULAR_TRANSMISSION_DEG,
    TRANSMISSION_BAND_DEG,
    dependent_coordinates,
    required_stroke,
    stroke_ratio,
    transmission_angle,
)
from .lagrange import LagrangeLoads, lagrange_cycle_loads
from .parameters import (
    CHARGE_FEEDER,
    DEVICES,
    PROJECTILE_FEEDER,
    FeederParameters,
    LinkInertia,
    parameter_table,
)
from .reactions import JointReactions, JointWrench, joint_reactions
from .results import read_csv, write_csv
from .simulation import ForceRule, ForwardMotion, constrained_dynamics, simulate
from .study import CycleStudy, run_cycle_study, write_cycle_study
from .urdf import urdf_string, write_urdfs
from .workspace import Workspace, workspace

__version__ = "0.1.0"

__all__ = [
    "CHARGE_FEEDER",
    "CLOSURE",
    "DEVICES",
    "INDEPENDENT_JOINTS",
    "PAPER_JOINTS",
    "PROJECTILE_FEEDER",
    "SINGULAR_TRANSMISSION_DEG",
    "TRANSMISSION_BAND_DEG",
    "ActuatorLoads",
    "ClosedChain",
    "ClosureFrameError",
    "CycleDynamics",
    "CycleKinematics",
    "CycleSpec",
    "CycleStudy",
    "CylinderPressures",
    "ElevationError",
    "Feeder",
    "FeederDynamics",
    "FeederError",
    "ForwardDivergenceError",
    "FeederParameters",
    "ForceRule",
    "ForwardMotion",
    "InertiaError",
    "InputError",
    "JointReactions",
    "JointWrench",
    "LagrangeLoads",
    "LinkInertia",
    "Partition",
    "Peak",
    "SingularPoseError",
    "UnreachablePoseError",
    "UrdfError",
    "ViewerPortError",
    "Workspace",
    "constrained_dynamics",
    "cycle_dynamics",
    "cylinder_pressures",
    "dependent_coordinates",
    "feeding_cycle",
    "inverse_dynamics",
    "joint_reactions",
    "kronecker_coriolis",
    "lagrange_cycle_loads",
    "load_closed_chain",
    "load_feeder",
    "parameter_table",
    "rack_force",
    "read_csv",
    "required_stroke",
    "run_cycle_study",
    "simulate",
    "stroke_ratio",
    "transmission_angle",
    "urdf_string",
    "workspace",
    "write_csv",
    "write_cycle_study",
    "write_urdfs",
]
