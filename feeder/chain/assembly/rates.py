"""A closed chain's initial joint rates from the rates a user gives for some of its joints
(``rates = {joint = value}`` in a mechanism file, ``feeder simulate --rate JOINT=VALUE``).

The rates q̇ of a closed chain at a closed pose q lie in the null space of the closure Jacobian
(J q̇ = 0). The rates r given for some one-coordinate joints (rad/s for revolute and continuous
joints, m/s for prismatic ones; selection E) are met in the least-squares sense over that null
space, and whatever they leave free is at minimum norm:

    q̇ = D N y,   y = (E D N)⁺ (D_E⁻¹ r),

with N an orthonormal basis of the null space of J D and D = diag(S) the speed scales of the
velocity gain (:class:`~feeder.chain.assembly.partition.Partition`: the mechanism's reach L [m]
at the model's zero pose for a length's rate, 1 for an angle's), so that rad/s and m/s are
weighed alike (a metre per second counts as L⁻¹ rad/s) and the result does not depend on the
unit of length.

* Rates of independent joints (an admissible choice, :func:`~feeder.chain.mobility.mobility`;
  or any joints whose rates the closure leaves free) are met exactly: the closure gives the
  others, as :meth:`Partition.velocity` does, and idle motions are at rest.
* Rates of more joints than the mechanism's freedoms (say every joint's, from a measurement) may
  contradict the closure: they are projected onto it (the least-squares fit above), and the
  report (:class:`InitialRates`) says what was given, what is used and how much it changed.
  A change beyond round-off (:data:`HONOURED`) is not refused — a measured state is never
  exactly closed — but warned (:class:`~feeder.exceptions.FeederWarning`) by the callers that
  start a run from it, and stated in their summaries.
* Rates of fewer joints than the freedoms leave the others at minimum norm (for a mechanism with
  no given rate: at rest); the report says how many freedoms the given rates fix.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_number
from ..kinematics.coordinates import length_rates
from ..kinematics.tree import reach
from ..model.closure import ClosedChain
from .rank import rank_tolerance

HONOURED = 1e-9
"""Largest change of a given rate, relative to the largest given (at least 1 rad/s or m/s),
that counts as round-off: the given rates are then used as they are. The null space is computed
to ~1e-15; a measured state rounded to 9 digits changes by ~1e-9."""


@dataclass(frozen=True)
class InitialRates:
    """A closed chain's initial rates and how they were obtained (module docstring).

    Attributes:
        v: The joint rates (nv,) [rad/s, m/s], closed (J q̇ = 0 to round-off).
        given: Joint name → the rate given.
        used: The same joints' rates in :attr:`v`.
        fixed: How many of the mechanism's freedoms the given rates fix (the rank of E D N).
        freedoms: The mechanism's degrees of freedom at the pose (nv − rank J).
        units: Joint name → the unit of its rate ("rad/s" or "m/s").
        closed: Whether the chain has closure rows (False: an open tree).
    """

    v: np.ndarray
    given: dict[str, float]
    used: dict[str, float]
    fixed: int
    freedoms: int
    units: dict[str, str]
    closed: bool

    def change(self) -> dict[str, float]:
        """Used − given rate of each given joint [rad/s, m/s]."""
        return {name: self.used[name] - value for name, value in self.given.items()}

    def projected(self) -> bool:
        """Whether the given rates contradict the closure beyond round-off (:data:`HONOURED`),
        so that :attr:`used` differs from :attr:`given`."""
        if not self.given:
            return False
        size = max(1.0, max(abs(x) for x in self.given.values()))
        return max(abs(x) for x in self.change().values()) > HONOURED * size

    def lines(self) -> list[str]:
        """The report as summary lines."""
        if not self.given:
            return ["initial rates: none given, the run starts at rest"]

        def listed(values: Mapping[str, float]) -> str:
            return ", ".join(f"{name} {x:.6g} {self.units[name]}" for name, x in values.items())

        lines = [f"initial rates given: {listed(self.given)}"]
        if self.projected():
            change = self.change()
            worst = max(change, key=lambda name: abs(change[name]))
            lines.append(
                f"  they contradict the closure: projected onto it (least squares over the closed "
                f"rates), used {listed(self.used)}; largest change {abs(change[worst]):.3g} "
                f"{self.units[worst]} ({worst}), ‖change‖ {math.hypot(*change.values()):.3g}"
            )
        elif self.closed:
            lines.append("  closed as given: the closure determines the other joints' rates")
        else:
            lines.append("  used as given (an open tree: no closure to meet)")
        if self.fixed < self.freedoms:
            lines.append(
                f"  they fix {self.fixed} of the mechanism's {self.freedoms} freedoms: the others "
                "start at minimum norm (the least motion that meets them)"
            )
        return lines


def initial_rates(chain: ClosedChain, q: np.ndarray, rates: Mapping[str, float]) -> InitialRates:
    """The closed rates at the closed pose ``q`` (nq,) that best meet the given ``rates`` (joint
    name → rad/s or m/s; module docstring).

    Raises:
        InputError: ``rates`` not a mapping of joint names to finite numbers, an unknown joint
            (with the nearest name), a joint with several coordinates (a ball, a free-flyer:
            give its one-coordinate neighbours), bad q.
    """
    if not isinstance(chain, ClosedChain):
        raise InputError(f"chain must be a ClosedChain, got {chain!r}")
    q = chain.check_q(q)
    if not isinstance(rates, Mapping):
        raise InputError(f"rates must map joint names to rates [rad/s, m/s], got {rates!r}")
    model = chain.model
    given = {name: check_number(f"the rate of {name!r}", value) for name, value in rates.items()}
    if not given:
        freedoms = _null_space(chain.jacobian(q)).shape[1]
        return InitialRates(np.zeros(model.nv), {}, {}, 0, freedoms, {}, chain.nc > 0)
    columns = chain.coordinate_columns(list(given), "rated")  # known one-coordinate joints
    lengths = length_rates(model)
    scale = np.where(lengths, reach(model, pin.neutral(model)[None]), 1.0)
    null = _null_space(chain.jacobian(q) * scale)  # (nv, freedoms), orthonormal
    target = np.array(list(given.values())) / scale[columns]
    y, _, fixed, _ = np.linalg.lstsq(null[columns], target, rcond=None)
    v = scale * (null @ y)
    units = {
        name: "m/s" if lengths[k] else "rad/s" for name, k in zip(given, columns, strict=True)
    }
    return InitialRates(
        v=v,
        given=given,
        used={name: float(v[k]) for name, k in zip(given, columns, strict=True)},
        fixed=int(fixed),
        freedoms=null.shape[1],
        units=units,
        closed=chain.nc > 0,
    )


def _null_space(jac: np.ndarray) -> np.ndarray:
    """An orthonormal basis (nv, nv − rank) of the null space of ``jac`` (nc, nv), singular
    values at or below :func:`~.rank.rank_tolerance` counting as zero."""
    if jac.shape[0] == 0:
        return np.eye(jac.shape[1])
    _, s, vt = np.linalg.svd(jac)
    return vt[int(np.sum(s > rank_tolerance(jac))) :].T
