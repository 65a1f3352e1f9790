"""Closed kinematic chains of any URDF: strict reading, loop closures, assembly, ∂M/∂q.

This layer knows nothing of the feeding device: it imports only :mod:`feeder.exceptions` and
:mod:`feeder.validation` (tests/test_layers.py checks it). Data flow: URDF text →
:func:`~feeder.chain.urdf.build_model` (checked) → :class:`ClosedChain` (model + closures) →
:class:`Partition` (independent/dependent coordinates, assembly at position, velocity and
acceleration level).
"""

from .assembly import POSITION_TOLERANCE, Partition
from .closure import ClosedChain, Closure, load_closed_chain
from .derivatives import mass_matrix_derivative
from .inertia import check_inertia
from .urdf import build_model, check_urdf, read_urdf

__all__ = [
    "POSITION_TOLERANCE",
    "ClosedChain",
    "Closure",
    "Partition",
    "build_model",
    "check_inertia",
    "check_urdf",
    "load_closed_chain",
    "mass_matrix_derivative",
    "read_urdf",
]
