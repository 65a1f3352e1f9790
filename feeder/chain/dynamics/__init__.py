"""Dynamics of a closed chain: inverse (loads, closure forces, reactions) and forward runs.

Public here: :class:`Controller` (:mod:`.forward_equations`), the protocol of an actuation with
states of its own that :func:`~feeder.chain.simulate` integrates with the mechanism's, and
:class:`ComputedTorque` (:mod:`.control`), one: actuated joints driven toward a reference motion
by the computed-torque law.
"""

from typing import TYPE_CHECKING

from ...lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .control import ComputedTorque
    from .forward_equations import Controller

__all__ = ["ComputedTorque", "Controller"]

__getattr__, __dir__ = lazy_names(
    __name__, {"ComputedTorque": ".control", "Controller": ".forward_equations"}, __all__
)
