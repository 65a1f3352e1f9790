"""The device's dynamics on Pinocchio: inverse dynamics of the closed chain (actuator loads and
pin force), every joint's reaction and the grip, the drives (cylinder pressures, rack force) and
the force-rule forward run; :func:`cycle_dynamics` runs them all over one loading cycle.

Data flow: :mod:`.models` (the models with and without payload) → :mod:`.inverse` (actuator
loads) → :mod:`.reactions` → :mod:`.drives` → :mod:`.forward` (the force-rule run) →
:mod:`.servo` and :mod:`.loading` (the run under position control on any base, the loading pose)
→ :mod:`.cycle` (all of them over one cycle).
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .cycle import FORWARD_TOLERANCE, CycleDynamics, cycle_dynamics
    from .forward import ForceRule, ForwardMotion, constrained_dynamics, simulate_feeder
    from .inverse import ActuatorLoads, SampledMotion, actuator_loads, check_cycle_motion
    from .loading import ControlledRun, LoadingPose, controlled_cycle
    from .models import FeederDynamics, feeder_dynamics
    from .reactions import JOINT_NAMES, JointReactions, JointWrench, pin_reactions
    from .servo import CycleServo, ServoGains

_SOURCES = {
    "ActuatorLoads": ".inverse",
    "ControlledRun": ".loading",
    "CycleDynamics": ".cycle",
    "CycleServo": ".servo",
    "FORWARD_TOLERANCE": ".cycle",
    "FeederDynamics": ".models",
    "ForceRule": ".forward",
    "ForwardMotion": ".forward",
    "JOINT_NAMES": ".reactions",
    "JointReactions": ".reactions",
    "JointWrench": ".reactions",
    "LoadingPose": ".loading",
    "SampledMotion": ".inverse",
    "ServoGains": ".servo",
    "actuator_loads": ".inverse",
    "check_cycle_motion": ".inverse",
    "constrained_dynamics": ".forward",
    "controlled_cycle": ".loading",
    "cycle_dynamics": ".cycle",
    "feeder_dynamics": ".models",
    "pin_reactions": ".reactions",
    "simulate_feeder": ".forward",
}
"""Public name → the module that defines it."""

__all__ = [
    "FORWARD_TOLERANCE",
    "JOINT_NAMES",
    "ActuatorLoads",
    "ControlledRun",
    "CycleDynamics",
    "CycleServo",
    "FeederDynamics",
    "ForceRule",
    "ForwardMotion",
    "JointReactions",
    "JointWrench",
    "LoadingPose",
    "SampledMotion",
    "ServoGains",
    "actuator_loads",
    "check_cycle_motion",
    "constrained_dynamics",
    "controlled_cycle",
    "cycle_dynamics",
    "feeder_dynamics",
    "pin_reactions",
    "simulate_feeder",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
