"""The motion: the feeding cycle's timing and rest-to-rest laws, the sampled cycle (closed loop
and payload path) and the payload's workspace (paper Figs. 4, 7, 8, 10)."""

from .cycle import CycleKinematics, feeding_cycle
from .laws import CycleSpec
from .workspace import Workspace, workspace

__all__ = ["CycleKinematics", "CycleSpec", "Workspace", "feeding_cycle", "workspace"]
