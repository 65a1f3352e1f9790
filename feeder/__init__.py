"""feeder: rigid-body analysis of the 152 mm SPH M77 ammunition feeding device, on Pinocchio.

Data flow: parameters (:mod:`feeder.parameters`) → URDF (:mod:`feeder.urdf`) → Pinocchio model
with the pin closure (:mod:`feeder.loading`, :mod:`feeder.closure`, :mod:`feeder.device`) →
kinematics (:mod:`feeder.assembly`, :mod:`feeder.kinematics`, :mod:`feeder.cycle`) → dynamics →
cross-check → results.
"""

from .assembly import Partition
from .closure import ClosedChain, load_closed_chain
from .cycle import CycleKinematics, CycleSpec, feeding_cycle
from .device import CLOSURE, INDEPENDENT_JOINTS, PAPER_JOINTS, Feeder, load_feeder
from .exceptions import (
    ClosureFrameError,
    ElevationError,
    FeederError,
    InertiaError,
    InputError,
    SingularPoseError,
    UnreachablePoseError,
    UrdfError,
)
from .kinematics import (
    TRANSMISSION_BAND_DEG,
    dependent_coordinates,
    required_stroke,
    stroke_ratio,
    transmission_angle,
)
from .parameters import (
    CHARGE_FEEDER,
    DEVICES,
    PROJECTILE_FEEDER,
    FeederParameters,
    LinkInertia,
    parameter_table,
)
from .urdf import urdf_string, write_urdfs

__version__ = "0.1.0"

__all__ = [
    "CHARGE_FEEDER",
    "CLOSURE",
    "DEVICES",
    "INDEPENDENT_JOINTS",
    "PAPER_JOINTS",
    "PROJECTILE_FEEDER",
    "TRANSMISSION_BAND_DEG",
    "ClosedChain",
    "ClosureFrameError",
    "CycleKinematics",
    "CycleSpec",
    "ElevationError",
    "Feeder",
    "FeederError",
    "FeederParameters",
    "InertiaError",
    "InputError",
    "LinkInertia",
    "Partition",
    "SingularPoseError",
    "UnreachablePoseError",
    "UrdfError",
    "dependent_coordinates",
    "feeding_cycle",
    "load_closed_chain",
    "load_feeder",
    "parameter_table",
    "required_stroke",
    "stroke_ratio",
    "transmission_angle",
    "urdf_string",
    "write_urdfs",
]
