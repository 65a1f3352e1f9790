"""The IFToMM rigid benchmark problems shipped in ``examples/iftomm`` against references computed
without multibody code: A01, the simple pendulum, against its closed form (Jacobi's elliptic
functions); A02, the N-four-bar, against the one equation of its crank angle that the
parallelogram leaves (integrated by SciPy alone), through every flat pose where the closure loses
N of its rank. The accuracy asked by the benchmark ("high") is 1e-3 [m, m/s, N].

The N-four-bar starts from its mechanism file's rate (``rates = { r0 = -1.0 }``), as
``feeder simulate`` runs it; the tests check that this is the benchmark's start (B0 at 1 m/s along
+x, the other joints' rates closed by Partition.velocity).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.special

from feeder.chain import Partition
from feeder.cli import main
from feeder.study.analyze import mount_mechanism
from feeder.study.csv import read_csv
from feeder.study.simulate import simulate_mechanism

from ..conftest import REPO

FOLDER = REPO / "examples" / "iftomm"
G = 9.81
HIGH = 1e-3
"""The IFToMM benchmark's "high" accuracy limit [m, m/s, N]."""


def _pendulum(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A01's P1 (N, 2) [m] and rod tension (N,) [N] in closed form: released at rest with the
    rod horizontal, its angle from the downward vertical is φ = 2 arcsin(k sn(K − ω t; k)),
    k = sin(π/4), ω = √(g/L), and the tension m (L φ̇² + g cos φ) = 3 m g cos φ (energy)."""
    k = math.sin(math.pi / 4.0)
    quarter = scipy.special.ellipk(k * k)
    sn, _, _, _ = scipy.special.ellipj(quarter - math.sqrt(G) * t, k * k)
    phi = 2.0 * np.arcsin(k * sn)
    return np.c_[np.sin(phi), -np.cos(phi)], 3.0 * G * np.cos(phi)


def test_a01_the_pendulum_follows_its_closed_form():
    """P1 and the rod's tension over the benchmark's 10 s (the pivot's reaction along the rod:
    the rod is massless), at the tolerances the README's command uses."""
    simulation = simulate_mechanism(
        FOLDER / "pendulum.toml", 10.0, samples=1001, rtol=1e-10, atol=1e-12
    )
    run = simulation.run
    position, tension = _pendulum(run.t)
    angle = run.q[:, 0]
    p1 = np.c_[np.cos(angle), np.sin(angle)]
    force = run.loads.joints["pivot"].force[:, :2]  # on the rod, from the ground
    pull = -np.einsum("ni,ni->n", force, p1)  # towards the pivot: the tension
    # measured 1.4e-8 m and 4e-7 N at rtol 1e-10; the benchmark asks 1e-3
    assert np.abs(p1 - position).max() <= HIGH / 100.0
    assert np.abs(pull - tension).max() <= HIGH / 100.0
    assert not run.singular and not run.indeterminate.any()


def _four_bar_reference(n: int, t: np.ndarray):
    """A02's crank angle θ(t) (rad), its rate, and the times the crank lies flat (θ = 0 mod π),
    from the one equation the parallelogram leaves: kinetic energy ½ I θ̇², I = (N + 1) m L²/3
    (the rockers about their pivots) + N m L² (the couplers translate with B), potential
    g sin θ ((N + 1) m L/2 + N m L); θ(0) = π/2, θ̇(0) = −1 rad/s (B0 at 1 m/s along +x)."""
    inertia, moment = (4 * n + 1) / 3.0, (3 * n + 1) / 2.0
    solution = scipy.integrate.solve_ivp(
        lambda _, y: [y[1], -G * moment * math.cos(y[0]) / inertia],
        (t[0], t[-1]), [math.pi / 2.0, -1.0], method="DOP853", rtol=1e-13, atol=1e-13,
        t_eval=t, events=lambda _, y: math.sin(y[0]),
    )  # fmt: skip
    return solution.y[0], solution.y[1], solution.t_events[0]


def _four_bar_run(n: int, duration: float, rtol: float, method: str = "DOP853"):
    """The run ``feeder simulate`` makes of the N-four-bar's files (the start rate theirs),
    after checking that start against the benchmark's, built here by Partition.velocity."""
    path = FOLDER / f"n_four_bar_{n}.toml"
    simulation = simulate_mechanism(
        path, duration, samples=int(round(duration * 100)) + 1, rtol=rtol, atol=rtol * 1e-2,
        method=method,
    )  # fmt: skip
    run, chain = simulation.run, simulation.chain
    spec, _, _, _, q0 = mount_mechanism(path, None, None)
    v0 = Partition(chain, spec.independent).velocity(q0, np.array([-1.0]))
    np.testing.assert_allclose(run.v[0], v0, rtol=0.0, atol=1e-12)  # round-off of the closure
    joint = chain.model.joints[chain.model.getJointId("r0")]
    return run, run.q[:, joint.idx_q : joint.idx_q + 2], run.v[:, joint.idx_v]


@pytest.mark.parametrize(("n", "duration", "passes"), [(2, 20.0, 20), (40, 20.0, 20)])
def test_a02_the_n_four_bar_passes_every_flat_pose_on_its_parallelogram(n, duration, passes):
    """B0 = L (cos θ, sin θ) and its velocity against the 1-DOF reference, through every pass of
    the flat pose (N = 2 and N = 40 over the benchmark's 20 s: 20 passes each; N = 40 takes
    ~10 s of CPU), the passes listed at the reference's times with the closure's rank
    2N → N → 2N."""
    run, crank, rate = _four_bar_run(n, duration, 1e-10)
    theta, theta_rate, flats = _four_bar_reference(n, run.t)
    b0 = np.c_[np.cos(theta), np.sin(theta)]
    b0_velocity = theta_rate[:, None] * np.c_[-np.sin(theta), np.cos(theta)]
    run_velocity = rate[:, None] * np.c_[-crank[:, 1], crank[:, 0]]
    # measured 1.3e-7 m and 9.1e-7 m/s (N = 2), 5.5e-7 m and 3.7e-6 m/s (N = 40) over 20 s:
    # the benchmark's 1e-3 met with room
    assert np.abs(crank - b0).max() <= HIGH
    assert np.abs(run_velocity - b0_velocity).max() <= HIGH
    times = np.array([singular.time for singular in run.singular])
    assert times.size == flats.size == passes
    # the run's phase error (its B0 error over B0's speed there, ~5 m/s) with room
    assert np.abs(times - flats).max() <= 1e-4
    for singular in run.singular:
        assert (singular.rank_before, singular.rank_at, singular.rank_after) == (2 * n, n, 2 * n)
    # no force acts but gravity: the energy is kept (measured over 20 s: 5.7e-8 J of 70 J at
    # N = 2, 1.8e-6 J of 1200 J at N = 40)
    assert run.energy_error() <= 1e-5 * run.kinetic.max()


@pytest.mark.parametrize("method", ["RK45", "Radau"])
def test_a02_passes_its_flat_poses_with_the_other_integrators(method):
    """The passes do not depend on the integrator: RK45 (a fourth-order dense output) and Radau
    (implicit) at the default tolerances carry the N = 2 four-bar through its first three flat
    poses on the parallelogram branch, at the reference's times (the expansion across each pose
    starts from its own accurate backward run, not from the method's dense output)."""
    run, crank, _ = _four_bar_run(2, 3.0, 1e-8, method)
    theta, _, flats = _four_bar_reference(2, run.t)
    # measured 4.6e-7 m (RK45) and 2.4e-7 m (Radau) over 3 s at rtol 1e-8: the benchmark's 1e-3
    assert np.abs(crank - np.c_[np.cos(theta), np.sin(theta)]).max() <= HIGH
    times = np.array([singular.time for singular in run.singular])
    assert times.size == flats.size == 3
    # the phase error over B0's speed at the flat pose (~5 m/s), with room: 6.4e-8 s (RK45)
    # and 3.9e-8 s (Radau) measured
    assert np.abs(times - flats).max() <= 1e-4


def test_a02_as_the_readme_runs_it(tmp_path, capsys):
    """The README's command (over 4 s: four flat poses) from the files alone: states.csv's crank
    follows the 1-DOF reference as the API's run does, and the summary lists every pass."""
    out = tmp_path / "a02"
    status = main(
        [
            "simulate",
            str(FOLDER / "n_four_bar_2.urdf"),
            "--closures",
            str(FOLDER / "n_four_bar_2.toml"),
            "--duration",
            "4",
            "--samples",
            "401",
            "--rtol",
            "1e-10",
            "--atol",
            "1e-12",
            "--no-figures",
            "--out",
            str(out),
        ]
    )
    assert status == 0, capsys.readouterr().err
    columns = read_csv(out / "states.csv")
    theta, _, flats = _four_bar_reference(2, columns["t"])
    # the same accuracy as the API's run above (it is the same run): the benchmark's 1e-3
    assert np.abs(np.cos(columns["q_r0"]) - np.cos(theta)).max() <= HIGH
    assert np.abs(np.sin(columns["q_r0"]) - np.sin(theta)).max() <= HIGH
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert f"singular positions passed: {flats.size}" in summary
    assert flats.size == 4
