"""Stiff runs: Hairer's test on an explicit method's steps, and the force element behind them.

An explicit Runge–Kutta method is stable only while h |λ| stays inside its stability region, λ
the fastest eigenvalue of the equations' Jacobian (on the negative real axis: 6.1 for DOP853,
3.25 for RK45, the Dormand–Prince pairs; Hairer & Wanner, *Solving ODEs II*, §IV.2, with its
automatic stiffness detection). A mode much
faster than the motion — a stiff damper, a stiff spring — then holds the step at about 6/|λ|
however smooth the motion is, and the run crawls: the four-bar with a damper of
c = 1e6 N·s/m between the ground and its rocker's tip takes 3 979 DOP853 steps for 0.1 s,
Radau 78 (same motion, energy balance 5e-13 J both).

Two ways to see it. Before the run, from the elements' stiffness and damping against the mass
matrix along their lines (ω² ≈ k gᵀM⁻¹g, λ ≈ c gᵀM⁻¹g, g = dℓ/dq): an estimate, which does not
know the step the tolerance alone would allow, and which misses the tension's own stiffness
T d²ℓ/dq² (a cylinder pushing 6e10 N has no k nor c). During the run, from the steps — chosen
here (:class:`StiffnessTest`, Hairer's test of the codes DOPRI5 and DOP853): after each accepted
step, h λ ≈ h ‖f(y₁) − f(ŷ)‖ / ‖y₁ − ŷ‖ from the step's end y₁ and its last stage ŷ, both at
t + h, evaluations the method has made anyway. It measures what holds the steps, so a run whose
steps follow its motion is not flagged: its h λ stayed below 3.3 over the examples (four-bar,
slider-crank, Bricard, Andrews' squeezer, the CAD exports) but for one step of 10 on
cassie_like, which the count of :data:`STIFF_STEPS` steps ignores; the damped four-bar above has
6.4 as its median over the run.

Once a run is found stiff, :func:`fastest_element` names the element: each element linearised
alone on the closed chain (its force's derivatives in q and q̇, numerically, on the chain's
free motions), and the largest eigenvalue magnitude of that linear system [1/s]. The same names
the element that makes a run fast rather than stiff, at the step cap (:func:`step_advice`): a
cylinder's bore of 80 mm typed as 80 m, 5 027 m² at 12 MPa on the four-bar, flings it about in
1.4e7 DOP853 steps per second of motion, a motion that an implicit method must follow as
closely (Radau: 3.6e8 steps per second), so Radau does not help it.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..assembly.newton import RANK_TOLERANCE
from .elements import BoundElements
from .inverse import ChainDynamics

STABILITY_BOUNDARY = {"DOP853": 6.1, "RK45": 3.25}
"""h |λ| beyond which an explicit method's step is held by its stability rather than by its
tolerance: where the stability region of DOP853 (order 8) and of RK45 (Dormand–Prince 5(4))
crosses the negative real axis, the values of Hairer's codes DOP853 and DOPRI5."""

STIFF_STEPS = 15
"""Accepted steps beyond :data:`STABILITY_BOUNDARY` (with fewer than :data:`NORMAL_STEPS` normal
ones in a row between them) that make a run stiff: Hairer's codes' count; a lone step near the
boundary is an explicit method's ordinary step-size control."""

NORMAL_STEPS = 6
"""Accepted steps in a row within the boundary that clear the count of stiff ones (Hairer's)."""

DIFFERENCE = 1e-7
"""Step [rad, m, rad/s, m/s] of the central differences of an element's generalized force: their
truncation error (∝ step², ~1e-14 of the force's scale) is below their round-off (ε/step,
~2e-9), so the rates come out to ~1e-9 of themselves, all that naming an element needs."""


class StiffnessTest:
    """Hairer's stiffness test (module docstring) over the accepted steps of one run.

    Args:
        method: The integrator's name; the test is idle for an implicit one (Radau, BDF).

    Attributes:
        time: Time [s] at which the run was found stiff, or None.
        rate: The estimate |λ| [1/s] of the step that made it stiff.
        step: That step's size h [s].
    """

    def __init__(self, method: str):
        self.boundary = STABILITY_BOUNDARY.get(method)
        self.stiff, self.normal = 0, 0
        self.time: float | None = None
        self.rate, self.step = 0.0, 0.0

    def check(self, solver) -> bool:
        """Count the step just accepted by ``solver`` (a SciPy Runge–Kutta solver); True once,
        at the step that makes the run stiff."""
        if self.boundary is None or self.time is not None:
            return False
        h = solver.t - solver.t_old
        last = solver.n_stages - 1  # its node is c = 1: the stage at t + h
        stage = solver.y_old + h * (solver.K[:last].T @ solver.A[last, :last])
        gap = float(np.linalg.norm(solver.y - stage))
        if gap == 0.0:
            return False
        h_lambda = h * float(np.linalg.norm(solver.K[-1] - solver.K[last])) / gap
        if h_lambda <= self.boundary:
            self.normal += 1
            if self.normal == NORMAL_STEPS:
                self.stiff = 0
            return False
        self.normal = 0
        self.stiff += 1
        if self.stiff < STIFF_STEPS:
            return False
        self.time, self.rate, self.step = float(solver.t), h_lambda / h, h
        return True


def element_rates(dyn: ChainDynamics, q: np.ndarray, v: np.ndarray, t: float) -> dict[str, float]:
    """Each force element's rate [1/s] at the closed state (q, v) and time t [s]: the largest
    |λ| of the closed chain linearised under that element alone,

        Zᵀ M Z ẍ + Zᵀ C Z ẋ + Zᵀ K Z x = 0,    K = −∂Q/∂q,  C = −∂Q/∂q̇,

    Q (nv,) the element's generalized force, Z (nv, d) an orthonormal basis of the chain's free
    motions (the null space of the closure rows J), M the mass matrix. A spring alone gives
    √(k gᵀ Z (ZᵀMZ)⁻¹ Zᵀ g), a damper c gᵀ Z (ZᵀMZ)⁻¹ Zᵀ g; the tension's own stiffness
    T d²ℓ/dq² comes with K. A free motion that moves no mass (an idle spin) has an infinite
    eigenvalue, left out."""
    chain, model = dyn.chain, dyn.chain.model
    jac = chain.jacobian(q)
    _, s, vt = np.linalg.svd(jac) if jac.size else (None, np.zeros(0), np.eye(model.nv))
    rank = int((s > RANK_TOLERANCE * max(float(s.max(initial=0.0)), 1.0)).sum())
    free = vt[rank:].T  # (nv, d)
    data = model.createData()
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    reduced_mass = free.T @ mass @ free
    d = free.shape[1]
    import scipy.linalg  # here: only a run whose steps are held pays its import (~0.2 s)

    rates = {}
    for element in dyn.elements.elements:
        alone = BoundElements(chain, [element])
        stiffness, damping = _derivatives(alone, q, v, t)
        left = np.block([[np.eye(d), np.zeros((d, d))], [np.zeros((d, d)), reduced_mass]])
        right = np.block(
            [[np.zeros((d, d)), np.eye(d)], [-free.T @ stiffness @ free, -free.T @ damping @ free]]
        )
        eigenvalues = scipy.linalg.eigvals(right, left) if d else np.zeros(0)
        finite = np.abs(eigenvalues[np.isfinite(eigenvalues)])
        rates[element.name] = float(finite.max(initial=0.0))
    return rates


def fastest_element(
    dyn: ChainDynamics, q: np.ndarray, v: np.ndarray, t: float
) -> tuple[str, float] | None:
    """The force element of the largest :func:`element_rates` and its rate [1/s], or None for a
    chain without elements."""
    rates = element_rates(dyn, q, v, t)
    if not rates:
        return None
    name = max(rates, key=rates.__getitem__)
    return name, rates[name]


def _derivatives(
    alone: BoundElements, q: np.ndarray, v: np.ndarray, t: float
) -> tuple[np.ndarray, np.ndarray]:
    """K = −∂Q/∂q (along the tangent space) and C = −∂Q/∂q̇, (nv, nv) each, by central
    differences of :data:`DIFFERENCE`."""
    model = alone.model
    nv = model.nv
    stiffness, damping = np.empty((nv, nv)), np.empty((nv, nv))
    for k in range(nv):
        step = np.zeros(nv)
        step[k] = DIFFERENCE
        ahead = alone.generalized(pin.integrate(model, q, step), v, t)[0]
        behind = alone.generalized(pin.integrate(model, q, -step), v, t)[0]
        stiffness[:, k] = -(ahead - behind) / (2.0 * DIFFERENCE)
        ahead = alone.generalized(q, v + step, t)[0]
        behind = alone.generalized(q, v - step, t)[0]
        damping[:, k] = -(ahead - behind) / (2.0 * DIFFERENCE)
    return stiffness, damping


PACE_SHARE = 0.01
"""A force element takes part in setting a run's pace when its rate [1/s] (:func:`element_rates`)
times the run's mean step [s] passes this: an explicit method follows a motion of rate λ in
steps of h λ ≈ 0.1–0.8 (the four-bar swinging under gravity: 0.3 in the median), so an element a
hundred times slower than that is not what holds the steps."""

RADAU = "the implicit method Radau (--method Radau, method='Radau') takes far fewer steps"
"""The advice to a stiff run."""


def stiff_warning(dyn: ChainDynamics, test: StiffnessTest, solver) -> str:
    """The warning of a run that ``test`` has just found stiff: its rate, the force element
    behind it (at the ``solver``'s state), the implicit method to use."""
    return (
        f"the run is stiff from t = {test.time:.6g} s: {type(solver).__name__}'s steps "
        f"({test.step:.2g} s) are held by its stability, not by its tolerance, at a rate of "
        f"≈ {test.rate:.2g} /s {_culprit(dyn, solver, test.rate)}: {RADAU}"
    )


def step_advice(dyn: ChainDynamics, test: StiffnessTest, solver, mean_step: float) -> str:
    """What holds the steps of a run stopped at the step cap, as the end of its message
    (:func:`~feeder.chain.dynamics.budget.step_cap_message`): stiffness, or the fastest force
    element at the ``solver``'s state when it takes part in the pace (:data:`PACE_SHARE`, its
    ``mean_step`` [s]), or nothing known (empty)."""
    if test.time is not None:
        return (
            f"; its steps are held by stiffness from t = {test.time:.6g} s, at "
            f"≈ {test.rate:.2g} /s {_culprit(dyn, solver, test.rate)}: {RADAU}"
        )
    fastest = fastest_element(dyn, *_state(dyn, solver))
    if fastest is None or fastest[1] * mean_step < PACE_SHARE:
        return ""
    return (
        f"; its fastest force element there, {fastest[0]}, moves it at ≈ {fastest[1]:.2g} /s "
        f"alone (its steps: {mean_step:.2g} s on average): check that element's values and units"
    )


def _culprit(dyn: ChainDynamics, solver, rate: float) -> str:
    """Which force element gives the rate ``rate`` [1/s] at the ``solver``'s state (text): the
    fastest, unless it is ten times slower."""
    fastest = fastest_element(dyn, *_state(dyn, solver))
    if fastest is None:
        return "from the mechanism's own equations (it has no force element)"
    name, element_rate = fastest
    if element_rate < 0.1 * rate:
        return (
            f"from the mechanism's own equations (its fastest force element, {name}, has "
            f"{element_rate:.2g} /s alone on it)"
        )
    return f"from {name} ({element_rate:.2g} /s alone on the mechanism)"


def _state(dyn: ChainDynamics, solver) -> tuple[np.ndarray, np.ndarray, float]:
    """(q, q̇, t) of the ``solver``'s state (q, q̇, work)."""
    nq, nv = dyn.chain.model.nq, dyn.chain.model.nv
    return solver.y[:nq], solver.y[nq : nq + nv], float(solver.t)
