"""What :mod:`feeder.chain`'s workflow returns, in one place for type annotations and
``isinstance`` checks; each type is defined (and documented) in the module named beside it.

* :class:`ChainLoads` — :func:`~feeder.chain.inverse_dynamics`: actuator loads, closure forces
  and wrenches (:class:`ClosureWrench`), every joint's reaction (:class:`JointWrench`) and the
  mount's (:class:`MountWrench`) (:mod:`feeder.chain.dynamics.inverse`, ``.reactions``);
* :class:`ForwardRun` — :func:`~feeder.chain.simulate` (:mod:`feeder.chain.dynamics.forward_run`),
  with the singular positions it passed (:class:`SingularPass`,
  :mod:`feeder.chain.dynamics.singular`);
* :class:`ControlRecord` — what a computed-torque controller did at a run's samples
  (:mod:`feeder.chain.dynamics.control`);
* :class:`HybridRun` — :func:`~feeder.chain.hybrid_run` (:mod:`feeder.chain.dynamics.hybrid`);
* :class:`Trajectory` — :func:`~feeder.chain.track`, and :class:`PoseCheck` — a pose checked by
  a :class:`~feeder.chain.Partition` (:mod:`feeder.chain.assembly`);
* :class:`ChainPose` — one configuration's kinematics, run once, and :class:`FrameMotion` —
  :func:`~feeder.chain.frame_motion` (:mod:`feeder.chain.kinematics`);
* :class:`MobilityReport` — :func:`~feeder.chain.mobility` (:mod:`feeder.chain.mobility`);
* :class:`BaseState` — a :class:`~feeder.chain.BaseMotion` at the sample times
  (:mod:`feeder.chain.model.base`).

The names load on first use: the device's dynamics name two of them, and must not import the
forward run's SciPy with them.
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .assembly.check import PoseCheck
    from .assembly.rates import InitialRates
    from .assembly.trajectory import Trajectory
    from .dynamics.control import ControlRecord
    from .dynamics.forward_run import ForwardRun
    from .dynamics.hybrid import HybridRun
    from .dynamics.inverse import ChainLoads
    from .dynamics.reactions import ClosureWrench, JointWrench, MountWrench
    from .dynamics.singular import SingularPass
    from .kinematics.frames import FrameMotion
    from .kinematics.pose import ChainPose
    from .mobility import MobilityReport
    from .model.base import BaseState

_SOURCES = {
    "BaseState": ".model.base",
    "ChainLoads": ".dynamics.inverse",
    "ChainPose": ".kinematics.pose",
    "ClosureWrench": ".dynamics.reactions",
    "ControlRecord": ".dynamics.control",
    "ForwardRun": ".dynamics.forward_run",
    "FrameMotion": ".kinematics.frames",
    "HybridRun": ".dynamics.hybrid",
    "InitialRates": ".assembly.rates",
    "JointWrench": ".dynamics.reactions",
    "MobilityReport": ".mobility",
    "MountWrench": ".dynamics.reactions",
    "PoseCheck": ".assembly.check",
    "SingularPass": ".dynamics.singular",
    "Trajectory": ".assembly.trajectory",
}
"""Public name → the module that defines it."""

__all__ = [
    "BaseState",
    "ChainLoads",
    "ChainPose",
    "ClosureWrench",
    "ControlRecord",
    "ForwardRun",
    "FrameMotion",
    "HybridRun",
    "InitialRates",
    "JointWrench",
    "MobilityReport",
    "MountWrench",
    "PoseCheck",
    "SingularPass",
    "Trajectory",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__, anchor=__package__)
