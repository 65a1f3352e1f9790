"""A joint under control, driven by its actuator or by a force element's push: what a
``[[control]]`` table says (:mod:`feeder.chain.readers.control`),
the settings of the computed-torque controller (:mod:`feeder.chain.dynamics.control`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True, eq=False)
class ControlSpec:
    """One controlled joint (:mod:`feeder.chain.readers.control`: the table's keys).

    Attributes:
        joint: The joint whose reference is tracked: an actuated joint, driven itself, or,
            with an :attr:`element`, a joint the element moves (not actuated).
        reference: The reference motion table's path.
        t: The table's times [s], (N,). q, v, a: The joint's reference position [rad or m], rate
            and acceleration, (N,) each.
        kp: Position gain K_p [1/s²]. kd: Rate gain K_d [1/s].
        force_limit: (low, high) bounds of the force [N or N·m] (±inf: none).
        rate_limit: Largest |du/dt| [N/s or N·m/s] (inf: none; finite only with a lag).
        lag: The actuator's time constant T [s] (0: none).
        area: Piston area [m²] of a hydraulic cylinder (None: not one); a joint's drive only.
        element: The force element (a spring or a cylinder, by name) whose push [N] drives the
            joint instead of the joint's own actuator (None: the joint is driven itself); the
            force, its limits and rate are then the push's [N, N/s].
        where: Where it was read (the file and table), for the messages.
    """

    joint: str
    reference: Path
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    kp: float
    kd: float
    force_limit: tuple[float, float] = (-math.inf, math.inf)
    rate_limit: float = math.inf
    lag: float = 0.0
    area: float | None = None
    where: str = ""
    element: str | None = None
