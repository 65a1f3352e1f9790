"""What a rigid model leaves undetermined (feeder.chain.dynamics.indeterminacy), against its
definition: the closure forces and reaction components that change when the per-row stiffness
of the cut changes (the same motion, the same drive loads, another share of the self-stress),
and nothing else. Bricard's linkage cut at a hinge has one self-stress in all five rows of its
cut; a four-bar whose coupler sits on a universal joint has none; one computation answers
``--check``, the summaries and the tables."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from feeder.chain import ChainDynamics, inverse_dynamics
from feeder.chain.assembly.newton import RANK_TOLERANCE
from feeder.chain.dynamics import indeterminacy as indeterminacy_module
from feeder.chain.dynamics.indeterminacy import COMPONENTS, indeterminacy
from feeder.chain.dynamics.newton_euler import joint_wrenches
from feeder.chain.kinematics.tree import tree_motion
from feeder.outputs import INDETERMINATE, write_simulation_outputs
from feeder.study.analyze import check_mechanism, mount_mechanism
from feeder.study.mechanism_table import indeterminate_columns
from feeder.study.simulate import simulate_mechanism

from ...conftest import REPO
from .fast_path_cases import NAMES, motion_case

BRICARD = REPO / "examples" / "bricard"
FOUR_BAR = REPO / "examples" / "four_bar"

CHANGED = 1e-7
"""[share of the largest load] A load that a change of stiffness moves: the self-stress share
changes by a fraction of the loads (~0.1 measured); the solve's round-off is ~1e-14 of them."""


@pytest.fixture(scope="module")
def bricard_hinge(tmp_path_factory):
    """Bricard's orthogonal 6R linkage cut at its first hinge: j1 locked (a fixed joint of the
    tree) and a revolute cut about the base's z in its place (5 rows); j2 drives it. Mounted away
    from the symmetric poses (j2 = 0: there the self-stress has no share in the cut's x and y
    forces)."""
    path = tmp_path_factory.mktemp("bricard_hinge") / "bricard.toml"
    path.write_text(
        f'[mechanism]\nurdf = "{(BRICARD / "bricard.urdf").as_posix()}"\nactuated = ["j2"]\n'
        'independent = ["j2"]\ngravity = [0.0, 0.0, -9.81]\njoint_types = {j1 = "FIXED"}\n'
        "pose = {j2 = 0.4, j3 = 2.07, j4 = 0.4, j5 = 2.07, j6 = 0.4}\n\n"
        '[[closure]]\nframes = ["tip", "base"]\ntype = "revolute"\naxis = [0.0, 0.0, 1.0]\n'
    )
    return path


def changed_by_stiffness(path, rng, frame: str) -> tuple[set[str], dict[str, set[str]]]:
    """The closure rows and joint reaction components (world axes) that three random per-row
    stiffnesses move, at the mechanism's assembled pose held at rest under gravity and a
    wrench on ``frame`` that also loads it across every plane (a planar mechanism's
    out-of-plane loads are zero under in-plane loads whatever the stiffness)."""
    spec, chain, _, _, q = mount_mechanism(path, None, None)
    zero = np.zeros((1, chain.model.nv))
    runs = []
    for _ in range(3):
        stiffness = {c.label: rng.uniform(0.2, 5.0, c.rows).tolist() for c in chain.closures}
        dyn = ChainDynamics(chain, spec.actuated, stiffness)
        wrench = {frame: np.array([0.3, -0.2, 1.0, 0.05, 0.1, -0.02])}  # [N, N·m]
        runs.append(inverse_dynamics(dyn, q[None], zero, zero, external=wrench))
    first = runs[0]
    scale = max(np.abs(w.force).max() for w in first.joints.values())
    rows, joints = set(), {}
    labels = chain.row_labels()
    for other in runs[1:]:
        moved = np.abs(other.closure_forces - first.closure_forces)[0] > CHANGED * scale
        rows |= {label for label, flag in zip(labels, moved, strict=True) if flag}
        for name, wrench in other.joints.items():
            base = first.joints[name]
            delta = np.hstack([wrench.force - base.force, wrench.moment - base.moment])[0]
            for component, value in zip(COMPONENTS, delta, strict=True):
                if abs(value) > CHANGED * scale:
                    joints.setdefault(name, set()).add(component)
        for name, tau in other.actuators.items():  # the drive loads are determined
            assert abs(tau[0] - first.actuators[name][0]) <= CHANGED * scale
    return rows, joints


def test_bricard_cut_at_a_hinge_has_all_five_rows_indeterminate(bricard_hinge, rng):
    spec, chain, _, _, q = mount_mechanism(bricard_hinge, None, None)
    found = indeterminacy(chain, q[None])
    assert found.self_stresses == 1
    assert found.rows == tuple(chain.row_labels())  # the five rows of the hinge cut
    rows, joints = changed_by_stiffness(bricard_hinge, rng, "link4")
    assert rows == set(found.rows)
    assert joints == {name: set(parts) for name, parts in found.joints.items()}


def test_check_and_summary_name_the_same_rows(bricard_hinge, tmp_path):
    """``--check`` at the assembled pose and the forward run's summary and sidecar list say the
    same five rows (once they said one and five)."""
    check = check_mechanism(bricard_hinge)
    labels = [f"tip-base:{row}" for row in ("fx", "fy", "m1", "m2", "fz")]
    line = next(x for x in check.text.splitlines() if "self-stresses of the closures" in x)
    assert line.startswith("  self-stresses of the closures: 1; statically indeterminate")
    assert sorted(line.split(": ")[-1].split(", ")) == sorted(labels)
    simulation = simulate_mechanism(bricard_hinge, 0.05, samples=11)
    summary = simulation.summary()
    rows = next(x for x in summary.splitlines() if x.startswith("    closure rows "))
    assert sorted(rows.removeprefix("    closure rows ").split(", ")) == sorted(labels)
    write_simulation_outputs(simulation, tmp_path / "out", figures=False)
    listed = (tmp_path / "out" / INDETERMINATE).read_text().splitlines()
    columns = [x for x in listed if not x.startswith("#")]
    assert columns == indeterminate_columns(simulation.run.loads.indeterminacy)
    assert set(columns) <= set(simulation.columns())
    assert "j2_force" in columns and "mount_force_x" not in columns


def test_the_planar_four_bar_s_out_of_plane_loads_are_indeterminate():
    """The four-bar moving in the x–y plane, cut at a pin (5 rows): its three out-of-plane rows
    are free (any force along them balances itself through the tree), and so are the
    out-of-plane components of every reaction (z force, x and y moments); the in-plane ones are
    determined. (A per-row stiffness cannot move them: the rows are free one by one, so the
    weighted minimum leaves them 0 whatever K — the joints carry it all.)"""
    spec, chain, _, _, q = mount_mechanism(FOUR_BAR / "closures.toml", None, None)
    found = indeterminacy(chain, q[None])
    assert found.self_stresses == 3
    assert set(found.rows) == {f"coupler_tip-rocker_tip:{r}" for r in ("fz", "m1", "m2")}
    out_of_plane = ("force_z", "moment_x", "moment_y")
    assert found.joints == dict.fromkeys(
        spec.independent + ("coupler_joint", "rocker_joint"), out_of_plane
    )
    assert found.closures == {"coupler_tip-rocker_tip": out_of_plane}


def test_a_determinate_four_bar_has_nothing_indeterminate(tmp_path):
    """The four-bar with its coupler on a universal joint (the pin's axis and one across the
    coupler) and cut at a ball: 4 freedoms, 3 independent rows, no self-stress."""
    text = (FOUR_BAR / "closures.toml").read_text()
    text = text.replace('type = "revolute"', 'type = "point"')
    text = text.replace("[mechanism]", '[mechanism]\njoint_types = {coupler_joint = "UJOINT_ZY"}')
    (tmp_path / "closures.toml").write_text(text)
    model = FOUR_BAR / "four_bar.urdf"
    spec, chain, _, _, q = mount_mechanism(tmp_path / "closures.toml", model, None)
    found = indeterminacy(chain, q[None])
    assert (found.self_stresses, found.rows, found.joints, found.closures) == (0, (), {}, {})
    check = check_mechanism(tmp_path / "closures.toml", model)
    assert "self-stresses of the closures: none" in check.text
    assert "statically indeterminate under" not in check.text
    simulation = simulate_mechanism(tmp_path / "closures.toml", 0.01, model=model, samples=3)
    assert "statically indeterminate under" not in simulation.summary()
    paths = write_simulation_outputs(simulation, tmp_path / "out", figures=False)
    assert INDETERMINATE not in {path.name for path in paths}


@pytest.mark.parametrize("name", NAMES)
def test_the_indeterminacy_equals_the_one_from_decomposed_self_stresses(
    name, tmp_path, monkeypatch
):
    """The lists come out the same when every pose's self-stresses come from the singular value
    decomposition of its closure Jacobian (the reference the unit-vector bases of
    rank.self_stress_bases replace: another orthonormal basis of the same span)."""
    chain, _, q, _, _ = motion_case(name, tmp_path)
    fast = indeterminacy(chain, q)

    def decomposed(jacobians):
        bases = []
        for jac in jacobians:
            u, s, _ = np.linalg.svd(jac, full_matrices=True)
            rank = int(np.sum(s > RANK_TOLERANCE * (np.abs(jac).max(initial=0.0) or 1.0)))
            bases.append(u[:, rank:].T)
        return bases

    monkeypatch.setattr(indeterminacy_module, "self_stress_bases", decomposed)
    assert indeterminacy(chain, q) == fast


def test_the_statics_pass_is_the_backward_pass_at_rest_without_gravity(rng):
    """joint_wrenches(inertia=False), which the reactions' pass takes, equals the whole
    backward pass of a motion at rest without gravity: every body term is then exactly zero."""
    chain, _, q, _, _ = motion_case("squeezer", None)
    model = chain.model
    rest = replace(tree_motion(model, q), gravity=np.zeros((q.shape[0], 3)))
    frame = model.getFrameId(model.frames[-1].name)
    external = [(frame, rng.normal(size=(q.shape[0], 6)))]
    full = joint_wrenches(model, rest, external)
    statics = joint_wrenches(model, rest, external, inertia=False)
    for whole, alone in zip(full, statics, strict=True):
        assert all(np.array_equal(x, y) for x, y in zip(whole, alone, strict=True))


@pytest.mark.parametrize("name", ["bricard", "n_four_bar_2", "cad_robot_delta"])
def test_the_self_stresses_largest_components_are_those_of_the_backward_pass(name, tmp_path):
    """The cuts' and joints' largest wrench components under the self-stresses, summed term by
    term over the frames each joint carries where a cut's rows carry force (the indeterminacy's
    shortcut), against the whole backward pass at rest (joint_wrenches without inertia) of
    every self-stress on every cut's frames at every sample, and the cuts' wrenches at every
    sample: the same sums in another order (round-off ~1e-15 of loads of size 1; the common
    ancestors of a cut's two frames, where the two terms cancel, included)."""
    from feeder.chain.assembly.rank import self_stress_bases
    from feeder.chain.dynamics.indeterminacy import _largest_components, subsample
    from feeder.chain.dynamics.reactions import closure_wrenches
    from feeder.chain.kinematics.rows import closure_kinematics

    chain, _, q, _, _ = motion_case(name, tmp_path)
    poses = tree_motion(chain.model, q[subsample(q.shape[0])])
    rows = closure_kinematics(chain, poses)
    bases = self_stress_bases(rows.jacobian)
    index = np.repeat(np.arange(len(bases)), [basis.shape[0] for basis in bases])
    lam = np.vstack(bases)
    cuts, peaks = _largest_components(chain, poses, rows, lam, index)
    wrenches, terms = closure_wrenches(chain, rows.at(index), lam)
    force, moment = joint_wrenches(chain.model, poses.at_rest(index), terms, inertia=False)
    whole = np.stack([np.abs(force).max(axis=1), np.abs(moment).max(axis=1)], axis=1)
    np.testing.assert_allclose(peaks[1:], whole[1:], rtol=0.0, atol=1e-12)
    each = [[np.abs(w.force).max(axis=0), np.abs(w.moment).max(axis=0)] for w in wrenches.values()]
    np.testing.assert_allclose(cuts, np.array(each), rtol=0.0, atol=1e-12)
    assert whole[1:].max() > 0.1  # the self-stresses load some joint
