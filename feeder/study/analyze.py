"""Analysis of a user's closed-chain mechanism (``feeder analyze``): its mobility, its motion
followed on one assembly branch, and the loads and reactions of every joint and cut.

Data flow: side-file and model (:mod:`feeder.chain.readers`) → :class:`~feeder.chain.ClosedChain`
→ mobility report at the first sample (:mod:`feeder.chain.mobility`) → the motion table's
independent coordinates tracked by continuation (:meth:`~feeder.chain.Partition.track`) →
inverse dynamics with every reaction (:mod:`feeder.chain.dynamics.inverse`) → the table
(:meth:`Analysis.columns`) and its summary.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..chain.assembly.partition import Partition
from ..chain.dynamics.inverse import ChainDynamics, ChainLoads, inverse_dynamics
from ..chain.dynamics.reactions import MountWrench
from ..chain.kinematics.joints import kind_of
from ..chain.mobility import MobilityReport, mobility
from ..chain.model.closure import ClosedChain
from ..chain.model.forces import ForceElement, JointSpring
from ..chain.readers.mechanism import load_mechanism, read_spec
from ..chain.readers.motion_table import MotionTable, read_motion
from ..chain.readers.pose import pose_from_values, read_pose
from ..chain.readers.spec import MechanismSpec
from ..exceptions import FeederWarning, InputError

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
        report: Mobility at the first sample.
        reference: The pose the mechanism was mounted from (nq,): the model's zero pose or the
            user's pose file.
        assembled: The closed pose nearest to it (nq,), where the motion starts from.
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

    def columns(self) -> dict[str, np.ndarray]:
        """The loads table, each column (N,), SI units, world axes:

        ``t``; the coordinates, rates and accelerations of every joint (:func:`joint_columns`;
        the accelerations include the idle motions', :attr:`ChainLoads.accelerations`);
        ``velocity_gain``; the loads (:func:`load_columns`).
        """
        cols: dict[str, np.ndarray] = {"t": self.motion.t}
        cols |= joint_columns(self.chain.model, self.q, self.v, self.loads.accelerations)
        cols["velocity_gain"] = self.gain
        return cols | load_columns(self.loads)

    def summary(self) -> str:
        """The mobility report, peaks of the loads and the indeterminacy convention, as text."""
        t = self.motion.t
        lines = [self.report.text(), *self.pose_lines()]
        lines.append(f"motion: {t.size} samples over {t[-1] - t[0]:.4g} s")
        lines.append(f"  {gravity_text(self.spec, self.chain)}")
        base = self.spec.base.describe() if self.spec.base else "standing level"
        lines.append(f"  base: {base}")
        if self.loads.idle_motions:
            lines.append(
                f"  {self.loads.idle_motions} idle motion(s): kept at minimum norm by the "
                "kinematics, their accelerations solved with the loads (no lock, no extra load)"
            )
        if self.motion.differentiated:
            lines.append(
                "  rates differentiated from positions for: "
                + ", ".join(self.motion.differentiated)
            )
        k = int(np.argmax(self.gain))
        lines.append(f"  largest velocity gain {self.gain[k]:.3g} at t = {t[k]:.4g} s")
        peaks = load_peaks(self.chain.model, t, self.loads, self.spec.forces)
        return "\n".join(lines + peaks)

    def pose_lines(self) -> list[str]:
        """The assembled pose as text (:func:`pose_lines`)."""
        return pose_lines(self.chain.model, self.reference, self.assembled)


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


def prismatic(model: pin.Model, joint: str) -> bool:
    """Whether ``joint`` is prismatic (its loads in N, not N·m)."""
    return kind_of(model.joints[model.getJointId(joint)]) == "prismatic"


def load_unit(model: pin.Model, joint: str) -> str:
    """The unit of a one-coordinate joint's generalized force: N (prismatic) or N·m."""
    return "N" if prismatic(model, joint) else "N·m"


def load_columns(loads: ChainLoads) -> dict[str, np.ndarray]:
    """The loads as table columns (N,), SI units, world axes: ``tau_<joint>`` of the actuated
    joints (N or N·m along the joint axis); ``<closure>_force_x|y|z`` and
    ``<closure>_moment_x|y|z`` (the cut's wrench on the body of its first frame, moment about
    that frame's origin); ``<joint>_force_x|y|z`` and ``<joint>_moment_x|y|z`` (the wrench the
    parent exerts on the child, about the joint's origin) and their magnitudes
    ``<joint>_force``, ``<joint>_moment``; ``<element>_force`` of each force element (a
    spring's or cylinder's tension [N], positive pulling its frames together; a joint spring's
    resistance [N·m or N]); the mount's wrench on the mechanism (about the model's origin)
    ``mount_force_x|y|z``, ``mount_moment_x|y|z`` in the level (world) axes and
    ``mount_force_vehicle_x|y|z``, ``mount_moment_vehicle_x|y|z`` in the base's axes, moving
    with it (the axes of every other column; the same on a base at rest)."""
    cols: dict[str, np.ndarray] = {}
    for name, values in loads.actuators.items():
        cols[f"tau_{name}"] = values
    for label, wrench in loads.closures.items():
        for what, vector in (("force", wrench.force), ("moment", wrench.moment)):
            for k, axis in enumerate("xyz"):
                cols[f"{label}_{what}_{axis}"] = vector[:, k]
    for name, wrench in loads.joints.items():
        for what, vector in (("force", wrench.force), ("moment", wrench.moment)):
            cols[f"{name}_{what}"] = np.linalg.norm(vector, axis=1)
            for k, axis in enumerate("xyz"):
                cols[f"{name}_{what}_{axis}"] = vector[:, k]
    for name, values in loads.elements.items():
        cols[f"{name}_force"] = values
    return cols | mount_columns(loads.mount)


def mount_columns(mount: MountWrench) -> dict[str, np.ndarray]:
    """The mount's wrench as table columns (:func:`load_columns`)."""
    cols: dict[str, np.ndarray] = {}
    for axes, force, moment in (
        ("", mount.level_force, mount.level_moment),
        ("_vehicle", mount.force, mount.moment),
    ):
        for what, vector in (("force", force), ("moment", moment)):
            for k, axis in enumerate("xyz"):
                cols[f"mount_{what}{axes}_{axis}"] = vector[:, k]
    return cols


def element_units(model: pin.Model, elements: Sequence[ForceElement]) -> dict[str, str]:
    """The unit of each force element's reported force, by name: N for a spring or a
    cylinder (tension), N·m or N for a joint spring on a revolute or prismatic joint."""
    return {
        element.name: load_unit(model, element.joint) if isinstance(element, JointSpring) else "N"
        for element in elements
    }


def load_peaks(
    model: pin.Model,
    t: np.ndarray,
    loads: ChainLoads,
    elements: Sequence[ForceElement],
    drives: bool = True,
) -> list[str]:
    """The peak of every drive load (if ``drives``), reaction force and element force with its
    time, and the statically indeterminate rows, as summary lines."""
    lines = []
    for name, values in loads.actuators.items() if drives else ():
        k = int(np.argmax(np.abs(values)))
        unit = load_unit(model, name)
        lines.append(
            f"  peak actuator load {name}: max |τ| = {abs(values[k]):.4g} {unit} "
            f"(sign {'+' if values[k] >= 0 else '−'}) at t = {t[k]:.4g} s"
        )
    for name, wrench in loads.joints.items():
        force = np.linalg.norm(wrench.force, axis=1)
        k = int(np.argmax(force))
        lines.append(f"  peak reaction force in {name}: {force[k]:.4g} N at t = {t[k]:.4g} s")
    for what, unit, vector in (
        ("force", "N", loads.mount.level_force),
        ("moment", "N·m", loads.mount.level_moment),
    ):
        size = np.linalg.norm(vector, axis=1)
        k = int(np.argmax(size))
        lines.append(
            f"  peak mount {what} (on the mechanism, about the model's origin): {size[k]:.4g} "
            f"{unit} at t = {t[k]:.4g} s"
        )
    units = element_units(model, elements)
    for name, values in loads.elements.items():
        k = int(np.argmax(np.abs(values)))
        lines.append(f"  peak force of {name}: {values[k]:.4g} {units[name]} at t = {t[k]:.4g} s")
    if loads.indeterminate:
        lines.append(
            "  statically indeterminate closure rows: "
            + ", ".join(loads.indeterminate)
            + f" ({loads.convention})"
        )
    return lines


def joint_columns(
    model: pin.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> dict[str, np.ndarray]:
    """Every joint's coordinates, rates and accelerations as table columns (N,), SI units:

    * revolute, prismatic: ``q_<j>``, ``v_<j>``, ``a_<j>`` (rad or m, and rates);
    * continuous: the same, ``q_<j>`` the angle atan2(sin, cos) in (−π, π];
    * ball (quaternion): ``q_<j>_rx|ry|rz``, its rotation vector [rad] (axis × angle, child
      relative to parent, parent axes), and ``q_<j>_qx|qy|qz|qw`` the unit quaternion;
      ``v_<j>_x|y|z``, ``a_<j>_x|y|z`` the angular velocity and acceleration in the child's axes;
    * universal, ball (ZYX), planar, free-flyer, translation: ``q_<j>_<k>``, ``v_<j>_<k>``,
      ``a_<j>_<k>`` for each of Pinocchio's coordinates and velocities k = 1, 2, … (planar:
      x, y, cos θ, sin θ and v_x, v_y, ω; free-flyer: position, quaternion and linear, angular
      velocity in the child's axes).
    """
    cols: dict[str, np.ndarray] = {}
    for j in range(1, model.njoints):
        cols |= _joint_columns(model, j, q, v, a)
    return cols


def _joint_columns(
    model: pin.Model, j: int, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> dict[str, np.ndarray]:
    """The columns of :func:`joint_columns` for joint ``j``."""
    cols: dict[str, np.ndarray] = {}
    joint, name = model.joints[j], model.names[j]
    qj = q[:, joint.idx_q : joint.idx_q + joint.nq]
    vj, aj = (x[:, joint.idx_v : joint.idx_v + joint.nv] for x in (v, a))
    if joint.nv == 1:
        angle = np.arctan2(qj[:, 1], qj[:, 0]) if joint.nq == 2 else qj[:, 0]
        cols |= {f"q_{name}": angle, f"v_{name}": vj[:, 0], f"a_{name}": aj[:, 0]}
    elif joint.shortname() == "JointModelSpherical":
        rotation = np.array([pin.log3(pin.Quaternion(x).matrix()) for x in qj])
        for k, axis in enumerate("xyz"):
            cols[f"q_{name}_r{axis}"] = rotation[:, k]
        for k, part in enumerate(("qx", "qy", "qz", "qw")):
            cols[f"q_{name}_{part}"] = qj[:, k]
        for k, axis in enumerate("xyz"):
            cols[f"v_{name}_{axis}"] = vj[:, k]
            cols[f"a_{name}_{axis}"] = aj[:, k]
    else:
        for k in range(joint.nq):
            cols[f"q_{name}_{k + 1}"] = qj[:, k]
        for k in range(joint.nv):
            cols[f"v_{name}_{k + 1}"] = vj[:, k]
            cols[f"a_{name}_{k + 1}"] = aj[:, k]
    return cols


def q_from_columns(model: pin.Model, cols: Mapping[str, np.ndarray]) -> np.ndarray:
    """The configurations (N, nq) a table's coordinate columns hold: the inverse of
    :func:`joint_columns` (a continuous joint's angle back to its cos, sin; a ball joint from its
    quaternion columns).

    Raises:
        InputError: A joint's coordinate column is missing (named).
    """

    def column(key: str) -> np.ndarray:
        if key not in cols:
            raise InputError(f"the table has no column {key!r}: it is not a table of this model")
        return np.asarray(cols[key], dtype=float)

    n = len(next(iter(cols.values())))
    q = np.empty((n, model.nq))
    for j in range(1, model.njoints):
        joint, name = model.joints[j], model.names[j]
        first = joint.idx_q
        if joint.nv == 1 and joint.nq == 2:
            angle = column(f"q_{name}")
            q[:, first], q[:, first + 1] = np.cos(angle), np.sin(angle)
        elif joint.nv == 1:
            q[:, first] = column(f"q_{name}")
        elif joint.shortname() == "JointModelSpherical":
            for k, part in enumerate(("qx", "qy", "qz", "qw")):
                q[:, first + k] = column(f"q_{name}_{part}")
        else:
            for k in range(joint.nq):
                q[:, first + k] = column(f"q_{name}_{k + 1}")
    return q


def pose_rows(model: pin.Model, q: np.ndarray) -> list[tuple[str, str, float]]:
    """A pose (nq,) as (joint, coordinate, value) rows, the coordinates of
    :func:`joint_columns`."""
    zero = np.zeros((1, model.nv))
    rows = []
    for j in range(1, model.njoints):
        name = model.names[j]
        for key, value in _joint_columns(model, j, q[None, :], zero, zero).items():
            if key.startswith("q_"):
                coordinate = key[len(name) + 2 :].lstrip("_") or "q"
                rows.append((name, coordinate, float(value[0])))
    return rows


def pose_lines(model: pin.Model, reference: np.ndarray, assembled: np.ndarray) -> list[str]:
    """The assembled pose as text: its distance from the reference and each joint's coordinates
    (:func:`pose_rows`)."""
    distance = float(np.linalg.norm(pin.difference(model, reference, assembled)))
    return [
        f"assembled pose (the closed pose nearest to the reference, ‖Δq‖ = {distance:.4g}):",
        *(f"  {name} {part} = {value:.9g}" for name, part, value in pose_rows(model, assembled)),
    ]


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


def check_mechanism(
    spec_path: str | Path, model: str | Path | None = None, pose: str | Path | None = None
) -> str:
    """The mobility report of a mechanism (``feeder analyze --check``) at its assembled pose:
    the closed pose nearest to the reference (the model's zero pose, or the pose file), which the
    report prints."""
    spec, chain, _, reference, assembled = mount_mechanism(spec_path, model, pose)
    report = mobility(chain, assembled, spec.independent).text()
    return "\n".join([report, *pose_lines(chain.model, reference, assembled)])


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
    table = read_motion(motion_path, spec.independent)
    q, v, a, gain = partition.track(assembled, table.x, table.dx, table.ddx, t=table.t)
    dyn = ChainDynamics(chain, spec.actuated, spec.stiffness, spec.forces, spec.base)
    loads = inverse_dynamics(dyn, q, v, a, t=table.t)
    warn_if_gravity_idle(spec, chain, q)
    report = mobility(chain, q[0], spec.independent)
    return Analysis(spec, chain, table, q, v, a, gain, loads, report, reference, assembled)
