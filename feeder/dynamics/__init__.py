"""The device's dynamics on Pinocchio: inverse dynamics of the closed chain (actuator loads and
pin force), every joint's reaction and the grip, the drives (cylinder pressures, rack force) and
the force-rule forward run; :func:`cycle_dynamics` runs them all over one loading cycle.

Data flow: :mod:`.models` (the models with and without payload) → :mod:`.inverse` (actuator
loads) → :mod:`.reactions` → :mod:`.drives` → :mod:`.forward` (the force-rule run) →
:mod:`.cycle` (all of them over one cycle).
"""

from .cycle import FORWARD_TOLERANCE, CycleDynamics, cycle_dynamics
from .forward import ForceRule, ForwardMotion, constrained_dynamics, simulate_feeder
from .inverse import ActuatorLoads, SampledMotion, actuator_loads, check_cycle_motion
from .models import FeederDynamics
from .reactions import JOINT_NAMES, JointReactions, JointWrench, pin_reactions

__all__ = [
    "FORWARD_TOLERANCE",
    "JOINT_NAMES",
    "ActuatorLoads",
    "CycleDynamics",
    "FeederDynamics",
    "ForceRule",
    "ForwardMotion",
    "JointReactions",
    "JointWrench",
    "SampledMotion",
    "actuator_loads",
    "check_cycle_motion",
    "constrained_dynamics",
    "cycle_dynamics",
    "pin_reactions",
    "simulate_feeder",
]
