"""Andrews' squeezing mechanism: ``examples/andrews_squeezer`` IS the published model, and
``feeder.chain`` runs it forward to the published solution.

The reference is the problem as published (Hairer & Wanner, Solving ODEs II, §VII.7, formula
(7.11); the "andrews" problem of the Test Set for IVP Solvers, Mazzia & Magherini): its mass matrix
M(q), forces f(q, q'), constraints g(q) and their Jacobian G(q) are copied below from the test
set's source, rforge/bvpsolve ``pkg/deTestSet/src/Ex_andrews.f`` (``andfunc``; the same formulas in
TuongL94/SimulationTools ``P2/squeezer.py``), the equations being M q'' = f − Gᵀλ, g = 0. The
URDF, read by Pinocchio alone (numpy and Pinocchio only, no feeder force-element code), must give
the same M (CRBA), the same velocity terms (RNEA), the same g and G (the closure frames' positions
and Jacobians), the same generalized forces of the spring and of the drive moment (Jᵀ f with the
parameters of ``squeezer.toml``), and so the published consistent accelerations and multipliers at
t = 0 (``reference.toml``).

Coordinates: the URDF joints carry the paper's names and angles; Pinocchio orders them depth-first
(the ground's children by name), q_pin = (β, Θ, δ, Φ, ε, Ω, γ), mapped by :data:`PAPER` below.

The last tests use the package on the shipped files only (the side-file's closures and force
elements, no hand-coded generalized force): the forward run against the published state at
t = 0.03 s, its t = 0 accelerations and closure forces against the published 30-digit values,
and the inverse dynamics of the run giving back the drive moment.
"""

from __future__ import annotations

import tomllib
import warnings

import numpy as np
import pinocchio as pin
import pytest

from ..conftest import REPO

FOLDER = REPO / "examples" / "andrews_squeezer"
URDF = FOLDER / "andrews_squeezer.urdf"

PAPER = ("beta", "theta", "gamma", "phi", "delta", "omega", "epsilon")
"""The paper's coordinates (β, Θ, γ, Φ, δ, Ω, ε), in its order: the URDF joint names."""
PINOCCHIO = ("beta", "theta", "delta", "phi", "epsilon", "omega", "gamma")
"""The order Pinocchio gives them (depth-first, the ground's child joints in name order)."""

# The published data (Ex_andrews.f, andfunc; SI units).
m1, m2, m3, m4, m5, m6, m7 = 0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498
i1, i2, i3, i4, i5, i6, i7 = 2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5
xa, ya, xb, yb, xc, yc = -0.06934, -0.00227, -0.03635, 0.03273, 0.014, 0.072
d, da, e, ea, rr, ra = 28e-3, 115e-4, 2e-2, 1421e-5, 7e-3, 92e-5
ss, sa, sb, sc, sd = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
ta, tb, u, ua, ub, zf, zt, fa = 2308e-5, 916e-5, 4e-2, 1228e-5, 449e-5, 2e-2, 4e-2, 1421e-5
mom, c0, l0 = 33e-3, 4530.0, 7785e-5

ROUND_OFF = 1e-13
"""Relative bound [-] of the model checks: both sides evaluate the same closed forms in double
precision, Pinocchio by composing 4×4 placements and spatial inertias, the paper by its
trigonometric sums; each is exact to a few ulps (~1e-16) of its largest term, and that term is the
scale used (max |M|, the link length d, the velocity terms' max, the spring's c0 ℓ0 times its lever
arm). Measured: ≤ 4e-16 (M), 3e-15 (velocity terms), 1e-15 (g, G), 2e-16 (forces); 1e-13 leaves a
margin of 30 or more, while a geometric or sign error shows at 1e-3 or more."""
KKT = 1e-10
"""Relative bound [-] of the t = 0 accelerations and multipliers against their 30-digit published
values, on the largest of each: the KKT matrix at q0 has condition ~5e4, so its double-precision
solution is good to ~5e4 · 1.1e-16 ≈ 6e-12 (measured 5e-16); the published values are exact to
their 30 digits."""


# ---------------------------------------------------------------------------------------------
# The published model, copied from andfunc (Ex_andrews.f): M, f, G, g in the paper's order.


def paper_mass(q: np.ndarray) -> np.ndarray:
    """M(q), the mass matrix of andfunc."""
    _, th, _, ph, _, om, _ = q
    m = np.zeros((7, 7))
    m[0, 0] = m1 * ra**2 + m2 * (rr**2 - 2 * da * rr * np.cos(th) + da**2) + i1 + i2
    m[1, 0] = m[0, 1] = m2 * (da**2 - da * rr * np.cos(th)) + i2
    m[1, 1] = m2 * da**2 + i2
    m[2, 2] = m3 * (sa**2 + sb**2) + i3
    m[3, 3] = m4 * (e - ea) ** 2 + i4
    m[4, 3] = m[3, 4] = m4 * ((e - ea) ** 2 + zt * (e - ea) * np.sin(ph)) + i4
    m[4, 4] = (
        m4 * (zt**2 + 2 * zt * (e - ea) * np.sin(ph) + (e - ea) ** 2)
        + m5 * (ta**2 + tb**2)
        + i4
        + i5
    )
    m[5, 5] = m6 * (zf - fa) ** 2 + i6
    m[6, 5] = m[5, 6] = m6 * ((zf - fa) ** 2 - u * (zf - fa) * np.sin(om)) + i6
    m[6, 6] = (
        m6 * ((zf - fa) ** 2 - 2 * u * (zf - fa) * np.sin(om) + u**2)
        + m7 * (ua**2 + ub**2)
        + i6
        + i7
    )
    return m


def paper_forces(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """f(q, q') of andfunc: the drive moment, the spring and the velocity terms (ff(1..7))."""
    _, th, ga, ph, _, om, _ = q
    bep, thp, _, php, dep, omp, epp = v
    xd = sd * np.cos(ga) + sc * np.sin(ga) + xb
    yd = sd * np.sin(ga) - sc * np.cos(ga) + yb
    lang = np.sqrt((xd - xc) ** 2 + (yd - yc) ** 2)
    force = -c0 * (lang - l0) / lang
    fx, fy = force * (xd - xc), force * (yd - yc)
    return np.array(
        [
            mom - m2 * da * rr * thp * (thp + 2 * bep) * np.sin(th),
            m2 * da * rr * bep**2 * np.sin(th),
            fx * (sc * np.cos(ga) - sd * np.sin(ga)) + fy * (sd * np.cos(ga) + sc * np.sin(ga)),
            m4 * zt * (e - ea) * dep**2 * np.cos(ph),
            -m4 * zt * (e - ea) * php * (php + 2 * dep) * np.cos(ph),
            -m6 * u * (zf - fa) * epp**2 * np.cos(om),
            m6 * u * (zf - fa) * omp * (omp + 2 * epp) * np.cos(om),
        ]
    )


def paper_constraints(q: np.ndarray) -> np.ndarray:
    """g(q) of andfunc (six rows)."""
    be, th, ga, ph, de, om, ep = q
    crank_x = rr * np.cos(be) - d * np.cos(be + th)
    crank_y = rr * np.sin(be) - d * np.sin(be + th)
    return np.array(
        [
            crank_x - ss * np.sin(ga) - xb,
            crank_y + ss * np.cos(ga) - yb,
            crank_x - e * np.sin(ph + de) - zt * np.cos(de) - xa,
            crank_y + e * np.cos(ph + de) - zt * np.sin(de) - ya,
            crank_x - zf * np.cos(om + ep) - u * np.sin(ep) - xa,
            crank_y - zf * np.sin(om + ep) + u * np.cos(ep) - ya,
        ]
    )


def paper_jacobian(q: np.ndarray) -> np.ndarray:
    """G(q) = ∂g/∂q of andfunc (gp)."""
    be, th, ga, ph, de, om, ep = q
    sibe, cobe, sibeth, cobeth = np.sin(be), np.cos(be), np.sin(be + th), np.cos(be + th)
    gp = np.zeros((6, 7))
    for row in (0, 2, 4):
        gp[row, 0] = -rr * sibe + d * sibeth
        gp[row, 1] = d * sibeth
        gp[row + 1, 0] = rr * cobe - d * cobeth
        gp[row + 1, 1] = -d * cobeth
    gp[0, 2] = -ss * np.cos(ga)
    gp[1, 2] = -ss * np.sin(ga)
    gp[2, 3] = -e * np.cos(ph + de)
    gp[2, 4] = -e * np.cos(ph + de) + zt * np.sin(de)
    gp[3, 3] = -e * np.sin(ph + de)
    gp[3, 4] = -e * np.sin(ph + de) - zt * np.cos(de)
    gp[4, 5] = zf * np.sin(om + ep)
    gp[4, 6] = zf * np.sin(om + ep) - u * np.cos(ep)
    gp[5, 5] = -zf * np.cos(om + ep)
    gp[5, 6] = -zf * np.cos(om + ep) - u * np.sin(ep)
    return gp


# ---------------------------------------------------------------------------------------------
# The example, read by Pinocchio.


@pytest.fixture(scope="module")
def files():
    with open(FOLDER / "squeezer.toml", "rb") as f:
        mechanism = tomllib.load(f)
    with open(FOLDER / "reference.toml", "rb") as f:
        reference = tomllib.load(f)
    return mechanism, reference


@pytest.fixture(scope="module")
def model(files):
    model = pin.buildModelFromUrdf(str(URDF))
    model.gravity = pin.Motion(np.array(files[0]["mechanism"]["gravity"]), np.zeros(3))
    return model


@pytest.fixture(scope="module")
def index(model):
    """Pinocchio's q index of each paper coordinate: q_pin[index] = q_paper."""
    return np.array([model.joints[model.getJointId(name)].idx_q for name in PAPER])


def to_pin(index: np.ndarray, paper: np.ndarray) -> np.ndarray:
    out = np.empty(7)
    out[index] = paper
    return out


def published(values) -> np.ndarray:
    return np.array([float(x) for x in values])


@pytest.fixture(scope="module")
def q0(files):
    return published(files[1]["initial"]["q"])


def random_states(count: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """(q, q') in the paper's order: any angles (M, f, g and G are defined everywhere, the
    closure need not hold) and rates of the size the mechanism reaches (~1e3 rad/s)."""
    rng = np.random.default_rng(seed)
    return [(rng.uniform(-np.pi, np.pi, 7), rng.uniform(-1e3, 1e3, 7)) for _ in range(count)]


class Pinocchio:
    """Pinocchio's quantities at a configuration given in the paper's order."""

    def __init__(self, model: pin.Model, index: np.ndarray, q: np.ndarray):
        self.model, self.data, self.index = model, model.createData(), index
        self.q = to_pin(index, q)
        pin.computeJointJacobians(model, self.data, self.q)
        pin.updateFramePlacements(model, self.data)

    def position(self, frame: str) -> np.ndarray:
        return self.data.oMf[self.model.getFrameId(frame)].translation.copy()

    def jacobian(self, frame: str) -> np.ndarray:
        """6 × 7 frame Jacobian, world axes at the frame's origin, columns in the paper's order."""
        j = pin.getFrameJacobian(
            self.model, self.data, self.model.getFrameId(frame), pin.LOCAL_WORLD_ALIGNED
        )
        return j[:, self.index]

    def mass(self) -> np.ndarray:
        upper = pin.crba(self.model, self.data, self.q)
        full = np.triu(upper) + np.triu(upper, 1).T
        return full[np.ix_(self.index, self.index)]

    def velocity_terms(self, v: np.ndarray) -> np.ndarray:
        """C(q, q') q' (RNEA without acceleration and gravity), paper's order."""
        rnea = pin.rnea(self.model, self.data, self.q, to_pin(self.index, v), np.zeros(7))
        return rnea[self.index]


def closure_gaps(state: Pinocchio, mechanism: dict) -> tuple[np.ndarray, np.ndarray]:
    """The closures of ``squeezer.toml``, in order: their gaps p(frames[0]) − p(frames[1]) (3 rows
    each) and the Jacobians of those gaps (linear rows)."""
    gaps, rows = [], []
    for closure in mechanism["closure"]:
        a, b = closure["frames"]
        gaps.append(state.position(a) - state.position(b))
        rows.append(state.jacobian(a)[:3] - state.jacobian(b)[:3])
    return np.concatenate(gaps), np.vstack(rows)


XY = np.array([0, 1, 3, 4, 6, 7])
"""The x–y rows of the three point closures' gaps: the paper's g1..g6 in order."""


def generalized_forces(state: Pinocchio, mechanism: dict) -> dict[str, np.ndarray]:
    """Jᵀ f of each ``[[force]]`` of ``squeezer.toml`` (paper's order): a spring pulls its two
    frames together with the tension k (ℓ − ℓ0); a load's force and moment (world axes) act on
    its frame's body."""
    out = {}
    for force in mechanism["force"]:
        if force["type"] == "spring":
            a, b = force["frames"]
            pa, pb = state.position(a), state.position(b)
            length = np.linalg.norm(pa - pb)
            tension = force["stiffness"] * (length - force["rest_length"])
            on_a = tension * (pb - pa) / length
            generalized = state.jacobian(a)[:3].T @ on_a + state.jacobian(b)[:3].T @ (-on_a)
        else:
            jacobian = state.jacobian(force["frame"])
            generalized = jacobian[:3].T @ np.array(force.get("force", [0.0, 0.0, 0.0]))
            generalized = generalized + jacobian[3:].T @ np.array(force.get("moment"))
        out[force["type"]] = generalized
    return out


# ---------------------------------------------------------------------------------------------


def test_joints_are_the_papers_coordinates_in_pinocchios_order(model, files, index):
    assert model.nq == model.nv == 7
    assert tuple(model.names[1:]) == PINOCCHIO == tuple(files[1]["coordinates"]["pinocchio"])
    assert tuple(files[1]["coordinates"]["paper"]) == PAPER
    np.testing.assert_array_equal(index, [0, 1, 6, 3, 2, 5, 4])
    for joint in model.joints[1:]:
        assert joint.shortname() == "JointModelRZ"  # revolute about +z, not continuous
    assert files[0]["mechanism"]["independent"] == ["beta"] == files[0]["mechanism"]["actuated"]


def test_the_project_reader_accepts_the_urdf():
    """The strict reader (tree, numbers, inertias, plausibility) takes the file without a word."""
    from feeder.chain.readers.urdf import build_model, read_urdf

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = build_model(read_urdf(URDF), str(URDF))
    assert tuple(model.names[1:]) == PINOCCHIO


def test_mass_matrix_is_the_papers(model, index, q0):
    """(a) CRBA = the paper's M(q), at q0 and anywhere (M does not need the closure)."""
    for q, _ in [(q0, None), *random_states(20, seed=1)]:
        mass = Pinocchio(model, index, q).mass()
        reference = paper_mass(q)
        scale = np.abs(reference).max()
        np.testing.assert_allclose(mass, reference, rtol=0.0, atol=ROUND_OFF * scale)


def test_velocity_terms_are_the_papers(model, index):
    """The paper's f(q, q') − f(q, 0) is −C(q, q') q' (Coriolis and centrifugal terms)."""
    for q, v in random_states(20, seed=2):
        terms = Pinocchio(model, index, q).velocity_terms(v)
        reference = -(paper_forces(q, v) - paper_forces(q, np.zeros(7)))
        scale = np.abs(reference).max()
        np.testing.assert_allclose(terms, reference, rtol=0.0, atol=ROUND_OFF * scale)


def test_closure_gaps_are_the_papers_constraints(model, index, files, q0):
    """(b) The x–y gaps of the three closures, F on body 2 minus F on body 3, 4, 6, are g1..g6
    (same sign, same order); z is zero (planar); at the published q0 they vanish."""
    mechanism = files[0]
    for q, _ in random_states(20, seed=3):
        gaps, _ = closure_gaps(Pinocchio(model, index, q), mechanism)
        np.testing.assert_allclose(gaps[XY], paper_constraints(q), rtol=0.0, atol=ROUND_OFF * d)
        np.testing.assert_array_equal(gaps[[2, 5, 8]], 0.0)
    gaps, _ = closure_gaps(Pinocchio(model, index, q0), mechanism)
    assert np.abs(gaps).max() <= 1e-12
    assert np.abs(paper_constraints(q0)).max() <= 1e-12


def test_closure_jacobian_is_the_papers(model, index, files, q0):
    """(c) The frame Jacobians' x–y rows of the gaps are G(q), row for row (so the same row space);
    at q0, G has full rank 6: one degree of freedom."""
    for q, _ in [(q0, None), *random_states(20, seed=4)]:
        _, rows = closure_gaps(Pinocchio(model, index, q), files[0])
        np.testing.assert_allclose(rows[XY], paper_jacobian(q), rtol=0.0, atol=ROUND_OFF * d)
        np.testing.assert_array_equal(rows[[2, 5, 8]], 0.0)
    assert np.linalg.matrix_rank(paper_jacobian(q0)) == 6


def test_spring_and_moment_are_the_papers_forces(model, index, files, q0):
    """(d) Jᵀ f of the spring (tension k (ℓ − ℓ0) pulling D and C together) and of the moment
    (world z on the crank) is the paper's f(q, 0): mom on β, the spring on γ, nothing else."""
    for q, _ in [(q0, None), *random_states(20, seed=5)]:
        forces = generalized_forces(Pinocchio(model, index, q), files[0])
        reference = paper_forces(q, np.zeros(7))
        scale = c0 * l0 * np.hypot(sd, sc)  # the spring's tension round-off times its lever
        total = forces["spring"] + forces["load"]
        np.testing.assert_allclose(total, reference, rtol=0.0, atol=ROUND_OFF * scale)
        np.testing.assert_allclose(forces["load"], [mom, 0, 0, 0, 0, 0, 0], rtol=0.0, atol=1e-17)
        assert np.count_nonzero(forces["spring"]) == 1 and forces["spring"][2] != 0.0


def test_published_initial_accelerations_and_multipliers(model, index, files, q0):
    """(e) M q'' + Gᵀλ = f, G q'' = 0 (q' = 0) at q0, everything from Pinocchio and the TOML
    forces, gives the published q''(0) and λ(0) (Lagrange multipliers of g1..g6)."""
    state = Pinocchio(model, index, q0)
    mass = state.mass()
    forces = generalized_forces(state, files[0])
    _, rows = closure_gaps(state, files[0])
    jacobian = rows[XY]
    kkt = np.block([[mass, jacobian.T], [jacobian, np.zeros((6, 6))]])
    solution = np.linalg.solve(
        kkt, np.concatenate([forces["spring"] + forces["load"], np.zeros(6)])
    )
    initial = files[1]["initial"]
    a, multipliers = published(initial["a"]), published(initial["multipliers"])
    np.testing.assert_allclose(solution[:7], a, rtol=0.0, atol=KKT * np.abs(a).max())
    np.testing.assert_allclose(
        solution[7:], multipliers, rtol=0.0, atol=KKT * np.abs(multipliers).max()
    )


def test_published_final_state_satisfies_the_closures(model, index, files):
    """The reference solution at t = 0.03 lies on the model's constraint manifold: its index-3
    integration kept g = 0 (measured gaps 7e-17 m) and G q' = 0 to the solver's tolerance
    (measured 1e-9 m/s, with q' ~ 1e3 rad/s on 0.03 m levers)."""
    final = files[1]["final"]
    q, v = np.array(final["q"]), np.array(final["v"])
    gaps, rows = closure_gaps(Pinocchio(model, index, q), files[0])
    assert np.abs(gaps).max() <= 1e-12
    assert np.abs(rows @ v).max() <= 1e-8


# -- the package on the shipped files ---------------------------------------------------------

POSITIONS = 1e-9
"""Relative error of q(0.03) (of max |q| ≈ 16 rad): the published values carry ~3e-10 of their own
(measured against an independent DOP853 run of the paper's formulas at 1e-11…1e-14: 2.7e-10);
the run at rtol 1e-10 adds ~1e-10 (measured)."""

VELOCITIES = 2e-7
"""Relative error of q′(0.03) (of max |q′| ≈ 1.4e3 rad/s): the published values carry ~5e-8 of
their own (measured 5.2e-8 as above); the run adds ~4e-10."""


@pytest.fixture(scope="module")
def squeezer():
    from feeder.chain import ChainDynamics, load_mechanism, read_spec

    spec = read_spec(FOLDER / "squeezer.toml")
    chain = load_mechanism(spec)
    return spec, chain, ChainDynamics(chain, spec.actuated, elements=spec.forces)


@pytest.fixture(scope="module")
def run(squeezer, files, index, q0):
    from feeder.chain import simulate

    _, _, dyn = squeezer
    return simulate(dyn, np.array([0.0, 0.015, 0.03]), to_pin(index, q0), np.zeros(7),
                    rtol=1e-10, atol=1e-12)  # fmt: skip


def test_the_run_reaches_the_published_state(run, files, index):
    final = files[1]["final"]
    q, v = to_pin(index, published(final["q"])), to_pin(index, published(final["v"]))
    assert np.abs(run.q[-1] - q).max() <= POSITIONS * np.abs(q).max()
    assert np.abs(run.v[-1] - v).max() <= VELOCITIES * np.abs(v).max()
    # no drive and no damper: the moment's work is the change of kinetic and spring energy
    assert run.energy_error() <= 1e-9 * np.abs(run.work).max()


def test_the_runs_first_sample_has_the_published_accelerations_and_forces(run, files, index):
    """q″(0) and λ(0) from Pinocchio's constraintDynamics and the inverse dynamics of the run,
    against the published 30-digit values (a KKT system of condition ~5e4: round-off ~1e-12).
    The package's closure force is the force on frame a's body (body 2): the paper's λ_k with
    the opposite sign, in the x–y rows (the z rows are the planar loops' redundant ones)."""
    initial = files[1]["initial"]
    a0 = to_pin(index, published(initial["a"]))
    np.testing.assert_allclose(run.a[0], a0, rtol=0.0, atol=KKT * np.abs(a0).max())
    multipliers = published(initial["multipliers"])
    np.testing.assert_allclose(
        -run.loads.closure_forces[0, XY],
        multipliers,
        rtol=0.0,
        atol=KKT * np.abs(multipliers).max(),
    )
    assert set(run.loads.indeterminacy.rows) == {
        "F_body2-F_body3:fz", "F_body2-F_body4:fz", "F_body2-F_body6:fz"
    }  # fmt: skip


def test_the_inverse_dynamics_give_back_the_drive_moment(squeezer, run):
    """The run's motion, with the spring as a force element and the crank actuated instead of
    loaded: the crank's drive is the published moment, 0.033 N·m, at every sample."""
    from feeder.chain import ChainDynamics, Load, inverse_dynamics

    spec, chain, _ = squeezer
    spring_only = [element for element in spec.forces if not isinstance(element, Load)]
    dyn = ChainDynamics(chain, ["beta"], elements=spring_only)
    loads = inverse_dynamics(dyn, run.q, run.v, run.a, t=run.t)
    moment = next(element for element in spec.forces if isinstance(element, Load)).moment
    # the run's accelerations are exact to the KKT's round-off (above): so is the moment
    np.testing.assert_allclose(loads.actuators["beta"], moment[2], rtol=KKT)
