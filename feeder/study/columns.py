"""The ``cycle.csv`` contract: the one place that names every column, its unit and its meaning.

:data:`COLUMNS` lists them in file order; :func:`cycle_columns` fills them from a cycle's
kinematics, dynamics and hand-derived loads. ``docs/REFERENCE.md`` documents each column for
users, and a test keeps the two in step. Vectors are in the world frame (origin at the cylinder
pivot B, x horizontal towards the breech, y up, z along the pivots); a magnitude column is
followed by its ``_x``, ``_y``, ``_z`` components. On a moving or tilted base the world frame is
the device's axes as they move with the hull; the mount's wrench is given both in the level
axes (``mount_force``, ``mount_moment``) and in the moving ones (``mount_*_vehicle``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..dynamics.cycle import CycleDynamics
from ..motion.cycle import CycleKinematics
from ..paper.lagrange import LagrangeLoads


@dataclass(frozen=True)
class Column:
    """One column of ``cycle.csv``.

    Attributes:
        name: Header name.
        unit: SI unit ("" for a count or flag).
        meaning: What the column holds, sign convention included.
    """

    name: str
    unit: str
    meaning: str


COORDINATES = ("phi1", "r2", "phi3", "phi4")
"""Suffixes of the generalized coordinates' columns, paper order (eq. 29)."""

_COORDINATE_UNITS = {
    "q": ("rad", "m", "rad", "rad"),
    "v": ("rad/s", "m/s", "rad/s", "rad/s"),
    "a": ("rad/s²", "m/s²", "rad/s²", "rad/s²"),
}

VectorGetter = Callable[[CycleDynamics], np.ndarray]

VECTORS: tuple[tuple[str, str, str, VectorGetter], ...] = (
    (
        "cylinder_frame_force",
        "N",
        "force of the frame on the cylinder through its trunnion at B (Fig. 12)",
        lambda d: d.reactions.joints["cylinder_frame"].force,
    ),
    (
        "piston_cylinder_force",
        "N",
        "side force of the cylinder's guides on the piston (the axial piston force excluded)",
        lambda d: d.reactions.joints["piston_cylinder"].constraint_force,
    ),
    (
        "piston_cylinder_moment",
        "N·m",
        "moment of the cylinder's guides on the piston about its centre of gravity S",
        lambda d: d.reactions.joints["piston_cylinder"].moment,
    ),
    (
        "piston_arm_force",
        "N",
        "force of the piston on the arm at the rod-eye pin (Fig. 13)",
        lambda d: d.reactions.closure_force,
    ),
    (
        "arm_frame_force",
        "N",
        "force of the frame on the arm through its pivot A",
        lambda d: d.reactions.joints["arm_frame"].force,
    ),
    (
        "arm_frame_moment",
        "N·m",
        "constraint moment of the frame on the arm about A (its pivot axis z excluded)",
        lambda d: d.reactions.joints["arm_frame"].constraint_moment,
    ),
    (
        "forearm_joint_force",
        "N",
        "force of the arm on the forearm through its hinge (Fig. 11)",
        lambda d: d.reactions.joints["forearm_arm"].force,
    ),
    (
        "forearm_joint_moment",
        "N·m",
        "constraint moment of the arm on the forearm about the hinge origin (the actuated hinge "
        "axis excluded)",
        lambda d: d.reactions.joints["forearm_arm"].constraint_moment,
    ),
    (
        "grip_force",
        "N",
        "force of the forearm on the payload (zero before the grip)",
        lambda d: d.reactions.grip_force,
    ),
    (
        "grip_moment",
        "N·m",
        "moment of the forearm on the payload about its centre of gravity (zero before the grip)",
        lambda d: d.reactions.grip_moment,
    ),
    (
        "mount_force",
        "N",
        "force of the vehicle on the device through its mount (the frame), level world axes",
        lambda d: d.reactions.mount.level_force,
    ),
    (
        "mount_moment",
        "N·m",
        "moment of the vehicle on the device through its mount about B, level world axes",
        lambda d: d.reactions.mount.level_moment,
    ),
    (
        "mount_force_vehicle",
        "N",
        "force of the vehicle on the device through its mount, the device's axes moving with "
        "the hull",
        lambda d: d.reactions.mount.force,
    ),
    (
        "mount_moment_vehicle",
        "N·m",
        "moment of the vehicle on the device about B, the device's axes moving with the hull",
        lambda d: d.reactions.mount.moment,
    ),
)
"""World-frame vector columns: name, unit, meaning and how to read them off the dynamics."""


def _columns() -> tuple[Column, ...]:
    cols = [
        Column("t", "s", "time from the start of the cycle"),
        Column("stage", "", "stage of the cycle: 1, 2 or 3"),
        Column("payload", "", "1 once the payload is gripped (end of stage 1), else 0"),
    ]
    what = {"q": "position", "v": "velocity", "a": "acceleration"}
    for prefix, units in _COORDINATE_UNITS.items():
        for name, unit in zip(COORDINATES, units, strict=True):
            cols.append(Column(f"{prefix}_{name}", unit, f"{what[prefix]} of coordinate {name}"))
    for axis in "xyz":
        cols.append(
            Column(f"projectile_{axis}", "m", f"payload centre of gravity, {axis} (Fig. 10)")
        )
    cols.append(Column("projectile_speed", "m/s", "payload centre-of-gravity speed (Fig. 8)"))
    for axis in "xyz":
        cols.append(
            Column(f"projectile_axis_{axis}", "", f"unit payload axis, nose first, {axis}")
        )
    cols += [
        Column(
            "transmission_angle_deg", "deg", "angle between piston axis and arm lever at the pin"
        ),
        Column("closure_residual", "m", "distance between the frames piston_pin and arm_pin"),
        Column(
            "piston_force", "N", "actuator force on piston_joint, positive extending (Fig. 14)"
        ),
        Column(
            "forearm_torque", "N·m", "actuator moment on forearm_joint, positive about its axis"
        ),
    ]
    for name, unit, meaning, _ in VECTORS:
        cols.append(Column(name, unit, f"magnitude of the {meaning}"))
        cols += [Column(f"{name}_{axis}", unit, f"{axis} component") for axis in "xyz"]
    cols += [
        Column(
            "cylinder_cap_pressure", "Pa", "cap-end chamber gauge pressure (pushes the rod out)"
        ),
        Column("cylinder_rod_pressure", "Pa", "rod-end chamber gauge pressure (pulls the rod in)"),
        Column("rack_force", "N", "rack force on the forearm pinion's pitch circle"),
        Column("forward_q_phi3", "rad", "arm angle of the force-rule forward run"),
        Column("forward_q_phi4", "rad", "forearm angle of the force-rule forward run"),
        Column("forward_closure_residual", "m", "pin gap of the forward run"),
        Column("controlled_q_phi3", "rad", "arm angle of the controlled forward run"),
        Column("controlled_q_phi4", "rad", "forearm angle of the controlled forward run"),
        Column("controlled_piston_force", "N", "piston force the controlled cylinder applies"),
        Column(
            "controlled_forearm_torque", "N·m", "forearm moment the controlled rack drive applies"
        ),
        Column("controlled_cylinder_cap_pressure", "Pa", "cap-end pressure of the controlled run"),
        Column("controlled_cylinder_rod_pressure", "Pa", "rod-end pressure of the controlled run"),
        Column("controlled_rack_force", "N", "rack force of the controlled run"),
        Column(
            "controlled_payload_error",
            "m",
            "distance of the payload's centre of gravity from where the cycle prescribes it",
        ),
        Column(
            "controlled_axis_error",
            "rad",
            "angle between the payload's axis and the axis the cycle prescribes",
        ),
        Column(
            "controlled_cylinder_saturated", "", "1 where the cylinder's command passes its limit"
        ),
        Column(
            "controlled_rack_saturated", "", "1 where the rack drive's command passes its limit"
        ),
        Column(
            "lagrange_piston_force",
            "N",
            "piston force from the hand-derived equations (the base standing level)",
        ),
        Column(
            "lagrange_forearm_torque",
            "N·m",
            "forearm moment from the hand-derived equations (the base standing level)",
        ),
        Column("lagrange_lambda1", "N", "multiplier of closure equation f1 (x)"),
        Column("lagrange_lambda2", "N", "multiplier of closure equation f2 (y)"),
    ]
    return tuple(cols)


COLUMNS: tuple[Column, ...] = _columns()
"""Every column of ``cycle.csv``, in file order. A run without the forward simulation omits the
``forward_*`` columns, one without the controlled run the ``controlled_*`` columns; ``feeder
kinematics`` writes the columns up to ``closure_residual``."""

KINEMATIC_COLUMNS = tuple(
    c.name for c in COLUMNS[: [c.name for c in COLUMNS].index("piston_force")]
)
"""The columns of the kinematics alone (``t`` … ``closure_residual``)."""


def kinematic_columns(k: CycleKinematics) -> dict[str, np.ndarray]:
    """The kinematic columns (:data:`KINEMATIC_COLUMNS`) of a sampled cycle, each (N,)."""
    cols: dict[str, np.ndarray] = {"t": k.t, "stage": k.stage, "payload": k.gripped}
    for prefix, values in (("q", k.q), ("v", k.v), ("a", k.a)):
        for i, name in enumerate(COORDINATES):
            cols[f"{prefix}_{name}"] = values[:, i]
    for i, axis in enumerate("xyz"):
        cols[f"projectile_{axis}"] = k.payload_position[:, i]
    cols["projectile_speed"] = np.linalg.norm(k.payload_velocity, axis=1)
    for i, axis in enumerate("xyz"):
        cols[f"projectile_axis_{axis}"] = k.payload_axis[:, i]
    cols["transmission_angle_deg"] = np.degrees(k.transmission_angle)
    cols["closure_residual"] = k.closure_residual
    return cols


def vector_quantities(d: CycleDynamics) -> dict[str, tuple[np.ndarray, str]]:
    """Every world-frame vector of :data:`VECTORS` by name: (values (N, 3), unit)."""
    return {name: (get(d), unit) for name, unit, _, get in VECTORS}


def cycle_columns(d: CycleDynamics, lagrange: LagrangeLoads) -> dict[str, np.ndarray]:
    """Every column of :data:`COLUMNS` (the ``forward_*`` and ``controlled_*`` ones only if
    those runs were made; the controlled run's at the cycle's samples, its hold left out)."""
    cols = kinematic_columns(d.kinematics)
    cols["piston_force"] = d.loads.piston_force
    cols["forearm_torque"] = d.loads.forearm_torque
    for name, (vector, _) in vector_quantities(d).items():
        cols[name] = np.linalg.norm(vector, axis=1)
        for i, axis in enumerate("xyz"):
            cols[f"{name}_{axis}"] = vector[:, i]
    cols["cylinder_cap_pressure"] = d.pressures.cap
    cols["cylinder_rod_pressure"] = d.pressures.rod
    cols["rack_force"] = d.rack_force
    if d.forward is not None:
        cols["forward_q_phi3"] = d.forward.q[:, 2]
        cols["forward_q_phi4"] = d.forward.q[:, 3]
        cols["forward_closure_residual"] = d.forward.closure_residual
    if d.controlled is not None:
        run, n = d.controlled, d.kinematics.t.size
        cols["controlled_q_phi3"] = run.q[:n, 2]
        cols["controlled_q_phi4"] = run.q[:n, 3]
        cols["controlled_piston_force"] = run.applied[:n, 0]
        cols["controlled_forearm_torque"] = run.applied[:n, 1]
        cols["controlled_cylinder_cap_pressure"] = run.pressures.cap[:n]
        cols["controlled_cylinder_rod_pressure"] = run.pressures.rod[:n]
        cols["controlled_rack_force"] = run.rack_force[:n]
        cols["controlled_payload_error"] = run.payload_error[:n]
        cols["controlled_axis_error"] = run.axis_error[:n]
        cols["controlled_cylinder_saturated"] = run.saturated[:n, 0].astype(int)
        cols["controlled_rack_saturated"] = run.saturated[:n, 1].astype(int)
    cols["lagrange_piston_force"] = lagrange.piston_force
    cols["lagrange_forearm_torque"] = lagrange.forearm_torque
    cols["lagrange_lambda1"] = lagrange.lambdas[:, 0]
    cols["lagrange_lambda2"] = lagrange.lambdas[:, 1]
    return cols
