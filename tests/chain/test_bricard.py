"""Bricard's orthogonal 6R linkage (``examples/bricard``): a redundant constraint. Its mobility is
1 where Grübler–Kutzbach counts 0, and it runs forward from rest with its energy kept and its
velocities on the one-dimensional tangent (a projection that trusted lstsq's default rank cut-off
took the round-off singular value of the redundant row for a real one and zeroed them)."""

from __future__ import annotations

import numpy as np

from feeder.chain import ChainDynamics, mobility, simulate
from feeder.study.analyze import mount_mechanism

from ..conftest import REPO

FILE = REPO / "examples" / "bricard" / "bricard.toml"


def test_mobility_is_one_where_the_count_says_zero():
    spec, chain, _, _, q = mount_mechanism(FILE, None, None)
    text = mobility(chain, q, spec.independent).text()
    assert "Grübler–Kutzbach mobility 6 − 6 = 0" in text
    assert "actual mobility 6 − 5 = 1" in text and "self-stresses of the closures: 1;" in text


def test_it_runs_forward_keeping_its_energy():
    spec, chain, _, _, q = mount_mechanism(FILE, None, None)
    run = simulate(ChainDynamics(chain, spec.actuated), np.linspace(0.0, 1.0, 101), q,
                   np.zeros(6), rtol=1e-10, atol=1e-12)  # fmt: skip
    assert run.kinetic.max() > 1.0  # it does move (3.4 J of kinetic energy measured)
    # no work is done: the energy is kept to the integrator's tolerance (2.6e-8 J measured at
    # rtol 1e-10, 1.5e-6 J at 1e-8: it converges with the tolerance); the lost-velocity bug
    # made it 0.13 J
    assert run.energy_error() <= 1e-6 * run.kinetic.max()
    assert run.drift() <= 1e-10
    # the undriven independent joint needs no drive in the run's inverse dynamics
    assert np.abs(run.loads.actuators["j2"]).max() <= 1e-6


def _release_acceleration(th: np.ndarray) -> np.ndarray:
    """q̈ at release from rest, from the linkage's own description (numpy only, independent of
    Pinocchio and of feeder's closures): six bars of L = 0.2 m along their x axes, 0.5 kg with
    their centre at L/2 and inertia diag(1e-4, 1/600, 1/600) kg·m², hinges about z, consecutive
    hinges turned by +90°, −90° alternately about x; the loop closed by the tip's pose (turned
    back by −90° about x) equal to the base's. At rest the motion follows the closure's
    one-dimensional tangent t (null vector of its Jacobian, by central differences): q̈ = t s̈,
    s̈ = −tᵀ∇V / tᵀ M t, M and ∇V from each bar's analytic Jacobian (z_k and z_k × (c − o_k))."""
    length, mass, g = 0.2, 0.5, 9.81
    rolls = [0.0] + [np.pi / 2.0 * (-1.0) ** k for k in range(5)]

    def rot(axis: int, angle: float) -> np.ndarray:
        c, s = np.cos(angle), np.sin(angle)
        i, j = [(1, 2), None, (0, 1)][axis]
        r = np.eye(3)
        r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
        return r

    def frames(q):
        r, p, out = np.eye(3), np.zeros(3), []
        for k in range(6):
            p = p + (r @ [length, 0.0, 0.0] if k else 0.0)
            r = r @ rot(0, rolls[k]) @ rot(2, q[k])
            out.append((r, p))
        return out

    def residual(q):
        r, p = frames(q)[-1]
        p, r = p + r @ [length, 0.0, 0.0], r @ rot(0, -np.pi / 2.0)
        return np.r_[p, r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]

    h = 1e-7
    jac = np.array([(residual(th + h * e) - residual(th - h * e)) / (2 * h) for e in np.eye(6)])
    tangent = np.linalg.svd(jac.T)[2][-1]
    inertia = np.diag([1e-4, 1.0 / 600.0, 1.0 / 600.0])
    placed = frames(th)
    m, grad = np.zeros((6, 6)), np.zeros(6)
    for i, (r, p) in enumerate(placed):
        centre = p + r @ [length / 2.0, 0.0, 0.0]
        jv, jw = np.zeros((3, 6)), np.zeros((3, 6))
        for k in range(i + 1):
            axis = placed[k][0][:, 2]
            jw[:, k], jv[:, k] = axis, np.cross(axis, centre - placed[k][1])
        m += mass * jv.T @ jv + jw.T @ r @ inertia @ r.T @ jw
        grad += mass * g * jv[2]
    return -(tangent @ grad) / (tangent @ m @ tangent) * tangent


def test_its_release_acceleration_is_the_one_of_its_own_description():
    """The run's first acceleration (at rest, from the symmetric pose: −66.61 rad/s² of j2, j4,
    j6) against the independent one: exact but for the closure Jacobian's central differences
    (h = 1e-7: ~1e-9 relative) and the closure's round-off at the start pose (1e-11 rad)."""
    spec, chain, _, _, q = mount_mechanism(FILE, None, None)
    run = simulate(ChainDynamics(chain, spec.actuated), np.linspace(0.0, 0.01, 3), q,
                   np.zeros(6), rtol=1e-10, atol=1e-12)  # fmt: skip
    names = [f"j{k}" for k in range(1, 7)]
    columns = [chain.model.joints[chain.model.getJointId(name)].idx_v for name in names]
    angles = np.array([q[chain.model.joints[chain.model.getJointId(n)].idx_q] for n in names])
    expected = _release_acceleration(angles)
    assert np.abs(expected).max() > 60.0  # it does fall (66.6 rad/s² measured)
    assert np.abs(run.a[0, columns] - expected).max() <= 1e-6 * np.abs(expected).max()
