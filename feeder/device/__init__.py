"""The feeding device: its parameters, the built-in devices, the URDF writer, the closed-form
loop and the device loaded in Pinocchio.

Data flow: :class:`FeederParameters` (numbers with units and sources) →
:func:`~feeder.device.loop.check_device` → :func:`urdf_string` → :class:`Feeder` (Pinocchio model
and the rod-eye pin closure, through :mod:`feeder.chain`). The loop's geometry lives once, in
:mod:`feeder.device.loop`.
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .builtin import CHARGE_FEEDER, DEVICES, PROJECTILE_FEEDER
    from .feeder import CLOSURE, INDEPENDENT_JOINTS, PAPER_JOINTS, Feeder, load_feeder
    from .loop import LoopState, loop_state, required_stroke, transmission_angle
    from .parameters import GRAVITY, FeederParameters, LinkInertia
    from .urdf_writer import urdf_string, write_urdfs

_SOURCES = {
    "CHARGE_FEEDER": ".builtin",
    "CLOSURE": ".feeder",
    "DEVICES": ".builtin",
    "Feeder": ".feeder",
    "FeederParameters": ".parameters",
    "GRAVITY": ".parameters",
    "INDEPENDENT_JOINTS": ".feeder",
    "LinkInertia": ".parameters",
    "LoopState": ".loop",
    "PAPER_JOINTS": ".feeder",
    "PROJECTILE_FEEDER": ".builtin",
    "load_feeder": ".feeder",
    "loop_state": ".loop",
    "required_stroke": ".loop",
    "transmission_angle": ".loop",
    "urdf_string": ".urdf_writer",
    "write_urdfs": ".urdf_writer",
}
"""Public name → the module that defines it."""

__all__ = [
    "CHARGE_FEEDER",
    "CLOSURE",
    "DEVICES",
    "GRAVITY",
    "INDEPENDENT_JOINTS",
    "PAPER_JOINTS",
    "PROJECTILE_FEEDER",
    "Feeder",
    "FeederParameters",
    "LinkInertia",
    "LoopState",
    "load_feeder",
    "loop_state",
    "required_stroke",
    "transmission_angle",
    "urdf_string",
    "write_urdfs",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
