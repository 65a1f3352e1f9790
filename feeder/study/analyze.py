"""Analysis of a user's closed-chain mechanism (``feeder analyze``): its mobility, its motion
followed on one assembly branch, and the loads and reactions of every joint and cut.

Data flow: side-file and model (:mod:`feeder.chain.readers`) → :class:`~feeder.chain.ClosedChain`
→ the closed pose nearest to the reference (the assembled pose) and the mobility report there
(:mod:`feeder.chain.mobility`, what ``--check`` prints) → the motion table's independent
coordinates tracked by continuation from it (:func:`~feeder.chain.track`) → inverse
dynamics with every reaction (:mod:`feeder.chain.dynamics.inverse`) — or, when the actuated
joints leave freedoms free that move mass, a hybrid run that integrates them while the actuated
joints follow the table (:mod:`feeder.chain.dynamics.hybrid`) — → the table
(:meth:`Analysis.columns`, its column names
:func:`~feeder.study.mechanism_table.column_stem`) and its summary.

The table's columns, units, peaks and pose lines are :mod:`feeder.study.mechanism_table`.
"""

from __future__ import annotations

import textwrap
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..chain.assembly.partition import Partition
from ..chain.assembly.tracking import track
from ..chain.dynamics.free_freedoms import free_freedoms
from ..chain.dynamics.hybrid import HybridRun, hybrid_run
from ..chain.dynamics.indeterminacy import indeterminacy
from ..chain.dynamics.inverse import CONVENTION, ChainDynamics, ChainLoads, inverse_dynamics
from ..chain.kinematics.frames import point_motion
from ..chain.mobility import NO_CLOSURE, MobilityReport, mobility
from ..chain.model.closure import ClosedChain
from ..chain.readers.mechanism import load_mechanism, read_spec
from ..chain.readers.motion_table import MotionTable, read_motion
from ..chain.readers.pose import pose_from_values, read_pose
from ..chain.readers.spec import MechanismSpec
from ..exceptions import FeederWarning, InputError
from .mechanism_table import (
    joint_columns,
    load_columns,
    load_peaks,
    merge_columns,
    point_columns,
    pose_lines,
)

GRAVITY_ROUND_OFF = 1e-9
"""Largest generalized gravity force, as a fraction of Σ m g (reach of the body's centre of
gravity), below which gravity counts as doing no work (:func:`warn_if_gravity_idle`). Gravity
perpendicular to every joint's motion (−z on revolute joints about z) gives exactly zero up to
round-off (~1e-16 of that scale per body, measured 0 on the four-bar); a mechanism whose plane
of motion is tilted from gravity by 1e-9 rad feels a gravity it could neglect anyway."""


@dataclass(frozen=True)
class Analysis:
    """A mechanism's motion and loads, N samples.

    Attributes:
        spec: The side-file's content.
        chain: The closed chain.
        motion: The prescribed motion of the independent joints.
        q, v, a: The whole chain's motion, (N, nq), (N, nv), (N, nv).
        gain: Velocity gain at every sample, (N,) (distance to a singular pose).
        loads: Actuator loads, closure forces and every joint's reaction.
        report: Mobility at the assembled pose (as ``feeder analyze --check`` reports it).
        reference: The pose the mechanism was mounted from (nq,): the model's zero pose or the
            user's pose file.
        assembled: The closed pose nearest to it (nq,), where the motion starts from.
        hybrid: The hybrid run when the actuated joints leave freedoms free that move mass
            (:mod:`feeder.chain.dynamics.hybrid`: they were integrated forward), else None.
    """

    spec: MechanismSpec
    chain: ClosedChain
    motion: MotionTable
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    gain: np.ndarray
    loads: ChainLoads
    report: MobilityReport
    reference: np.ndarray
    assembled: np.ndarray
    hybrid: HybridRun | None = None

    def columns(self) -> dict[str, np.ndarray]:
        """The loads table, each column (N,), SI units, world axes:

        ``t``; the coordinates, rates and accelerations of every joint (:func:`joint_columns`;
        the accelerations include the idle motions', :attr:`ChainLoads.accelerations`); the
        mechanism file's points (:func:`point_columns`); ``velocity_gain``; the loads
        (:func:`load_columns`).
        """
        a = self.loads.accelerations
        points = point_motion(self.chain, self.spec.points, self.q, self.v, a)
        return merge_columns(
            {"t": self.motion.t},
            joint_columns(self.chain.model, self.q, self.v, a),
            point_columns(points),
            {"velocity_gain": self.gain},
            load_columns(self.loads),
        )

    def summary(self) -> str:
        """The mobility report at the assembled pose and that pose (:func:`mount_lines`, as
        ``feeder analyze --check`` prints them), the motion, the peaks of the loads and the
        indeterminacy convention, as text."""
        t = self.motion.t
        lines = mount_lines(self.report, self.chain.model, self.reference, self.assembled)
        lines.append(
            f"motion: {t.size} samples over {t[-1] - t[0]:.4g} s, its first sample reached from "
            "the assembled pose by continuation"
        )
        lines.append(f"  {gravity_text(self.spec, self.chain)}")
        lines.append(f"  {base_text(self.spec)}")
        if self.loads.idle_motions:
            lines.append(
                f"  {self.loads.idle_motions} idle motion(s): kept at minimum norm by the "
                "kinematics, their accelerations solved with the loads (no lock, no extra load)"
            )
        if self.hybrid is not None:
            lines += [f"  {line}" for line in self.hybrid.text(self.chain.model)]
        if self.motion.differentiated:
            lines.append(
                "  rates differentiated from positions for: "
                + ", ".join(self.motion.differentiated)
            )
        k = int(np.argmax(self.gain))
        if self.chain.nc:
            lines.append(
                f"  velocity gain at the first sample (t = {t[0]:.4g} s) {self.gain[0]:.3g}, "
                f"largest {self.gain[k]:.3g} at t = {t[k]:.4g} s ({self.report.gain_definition})"
            )
        else:
            lines.append(f"  velocity gain: none, {NO_CLOSURE}")
        peaks = load_peaks(self.chain.model, t, self.loads, self.spec.forces)
        return "\n".join(lines + peaks)


def gravity_text(spec: MechanismSpec, chain: ClosedChain) -> str:
    """The gravity the run used [m/s²] and whether the mechanism file gave it or it was assumed
    (the model's default), as text."""
    value = np.round(chain.model.gravity.linear, 6).tolist()
    source = (
        "assumed: the mechanism file gives no gravity, the model's is used"
        if spec.gravity is None
        else "from the mechanism file"
    )
    return f"gravity {value} m/s² ({source})"


def base_text(spec: MechanismSpec) -> str:
    """The base's motion the mechanism file gives (its ``[base]``), as text."""
    return f"base: {spec.base.describe() if spec.base else 'standing level'}"


def warn_if_gravity_idle(spec: MechanismSpec, chain: ClosedChain, q: np.ndarray) -> None:
    """Warn (:class:`~feeder.exceptions.FeederWarning`) when gravity is not zero but does no
    work on the mechanism: its generalized force (nv,) is zero at every sample of ``q`` (N, nq)
    to :data:`GRAVITY_ROUND_OFF` (e.g. −z on a mechanism moving in the x–y plane), so every load
    it would cause is zero."""
    model, data = chain.model, chain.model.createData()
    if not np.any(model.gravity.linear):
        return
    masses = np.array([inertia.mass for inertia in model.inertias])
    largest = scale = 0.0
    for x in q:
        largest = max(largest, float(np.abs(pin.computeGeneralizedGravity(model, data, x)).max()))
        centres = [
            placement.act(inertia.lever)
            for placement, inertia in zip(data.oMi, model.inertias, strict=True)
        ]
        scale = max(scale, float(masses @ np.linalg.norm(centres, axis=1)))
    scale *= float(np.linalg.norm(model.gravity.linear))
    if largest <= GRAVITY_ROUND_OFF * max(scale, 1e-300):
        warnings.warn(
            f"{gravity_text(spec, chain)} does no work on the mechanism (its generalized force is "
            "zero at every sample): every load it would cause is 0; give [mechanism] gravity "
            "along the plane of motion, e.g. [0, -9.81, 0] for one moving in the x-y plane",
            FeederWarning,
            stacklevel=3,
        )


def mount_lines(
    report: MobilityReport, model: pin.Model, reference: np.ndarray, assembled: np.ndarray
) -> list[str]:
    """The mobility report measured at the assembled pose, under a heading that says so, then
    that pose (:func:`pose_lines`): the summaries' first lines."""
    return [
        "mobility at the assembled pose (the closed pose nearest to the reference, below):",
        textwrap.indent(report.text(), "  "),
        *pose_lines(model, reference, assembled),
    ]


def free_joints(
    spec: MechanismSpec, dyn: ChainDynamics, report: MobilityReport, assembled: np.ndarray
) -> tuple[tuple[str, ...], ...]:
    """The joints of each freedom that the actuated joints leave free and that moves mass at the
    assembled pose (:mod:`feeder.chain.dynamics.free_freedoms`), when the independent joints do
    not determine the mechanism there (``report``) and are the actuated ones: ``analyze`` then
    integrates them forward (a hybrid run); empty otherwise."""
    if report.determined is None or set(spec.actuated) != set(spec.independent):
        return ()
    return free_freedoms(dyn, assembled).joints


def mount_mechanism(spec_path, model, pose):
    """The side-file, its chain, the partition of its independent joints, the reference pose
    (the pose file, or the side-file's pose, or the model's zero pose) and the closed pose
    nearest to it."""
    spec = read_spec(spec_path, model)
    chain = load_mechanism(spec)
    partition = Partition(chain, spec.independent)
    if pose is not None:
        reference = read_pose(pose, chain.model)
    else:
        reference = pose_from_values(list(spec.pose), chain.model)
    return spec, chain, partition, reference, partition.mount(reference)


@dataclass(frozen=True)
class MechanismCheck:
    """A mechanism's mobility report at its assembled pose (``feeder analyze --check``).

    Attributes:
        report: The report, for the side-file's independent joints.
        text: The report and the assembled pose as text (:func:`mount_lines`).
    """

    report: MobilityReport
    text: str
    free: tuple[tuple[str, ...], ...] = ()

    @property
    def drives(self) -> bool:
        """Whether ``feeder analyze`` can follow a motion of the independent joints there: they
        determine the mechanism (up to idle motions; :attr:`MobilityReport.determined` is None),
        or the freedoms they leave free move mass and are integrated (:attr:`free`: the joints
        of each)."""
        return self.report.determined is None or bool(self.free)


def check_mechanism(
    spec_path: str | Path, model: str | Path | None = None, pose: str | Path | None = None
) -> MechanismCheck:
    """The mobility report of a mechanism (``feeder analyze --check``) at its assembled pose:
    the closed pose nearest to the reference (the model's zero pose, or the pose file), where
    ``feeder analyze`` starts and measures its own report; then the reaction components its
    self-stresses leave indeterminate there
    (:func:`~feeder.chain.dynamics.indeterminacy.indeterminacy`, as the summaries say them)."""
    spec, chain, _, reference, assembled = mount_mechanism(spec_path, model, pose)
    report = mobility(chain, assembled, spec.independent)
    lines = mount_lines(report, chain.model, reference, assembled)
    stresses = indeterminacy(chain, assembled[None]).lines(CONVENTION, rows=False)
    lines += ["  " + line for line in stresses]
    free = ()
    if report.determined is not None:
        dyn = ChainDynamics(chain, spec.actuated, spec.stiffness, spec.forces, spec.base)
        free = free_joints(spec, dyn, report, assembled)
    if free:
        lines.append(
            f"{len(free)} freedom(s) left free move mass ("
            + "; ".join(", ".join(joints) for joints in free)
            + "): feeder analyze --motion integrates them forward (a hybrid run)"
        )
    return MechanismCheck(report, "\n".join(lines), free)


def analyze(
    spec_path: str | Path,
    motion_path: str | Path,
    model: str | Path | None = None,
    pose: str | Path | None = None,
) -> Analysis:
    """Follow the motion table on one branch and compute every load and reaction.

    Args:
        spec_path: The closure side-file (TOML, :mod:`feeder.chain.readers.side_file`).
        motion_path: The motion table (CSV).
        model: The model file, overriding the side-file's.
        pose: A pose file (:mod:`feeder.chain.readers.pose`) that picks the assembly branch
            (default: the model's zero pose); the mechanism is mounted onto the closed pose
            nearest to it, then its independent joints follow the table.

    Raises:
        FeederError: Bad files, an unreachable or singular pose, a motion the actuated joints
            cannot produce (each with its own message).
    """
    spec, chain, partition, reference, assembled = mount_mechanism(spec_path, model, pose)
    if not spec.actuated:
        raise InputError(
            f"{spec_path}: the motion's loads need actuated joints, and [mechanism] actuated is "
            "empty: name the joints that drive it (a passive mechanism runs forward with "
            "feeder simulate)"
        )
    table = read_motion(motion_path, spec.independent)
    dyn = ChainDynamics(chain, spec.actuated, spec.stiffness, spec.forces, spec.base)
    report = mobility(chain, assembled, spec.independent)
    hybrid = None
    if free_joints(spec, dyn, report, assembled):  # freedoms that move mass: integrated forward
        order = [spec.independent.index(name) for name in spec.actuated]
        x, dx, ddx = (values[:, order] for values in (table.x, table.dx, table.ddx))
        hybrid = hybrid_run(dyn, table.t, x, dx, ddx, assembled)
    if hybrid is None:
        motion = track(partition, assembled, table.x, table.dx, table.ddx, t=table.t)
        kinematics = (motion.q, motion.v, motion.a, motion.gain)
        loads = inverse_dynamics(dyn, motion.q, motion.v, motion.a, t=table.t)
    else:
        gain = np.array([partition.gain(q) for q in hybrid.q])
        kinematics, loads = (hybrid.q, hybrid.v, hybrid.a, gain), hybrid.loads
    warn_if_gravity_idle(spec, chain, kinematics[0])
    return Analysis(spec, chain, table, *kinematics, loads, report, reference, assembled, hybrid)
