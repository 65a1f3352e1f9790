"""The table of a mechanism's analysis or run (``loads.csv``, ``states.csv``) as a contract:
its column names (:func:`column_stem`: letters, digits and ``_`` only, so that numpy's and
pandas' readers keep them), their units, the drive loads' and reactions' columns, the peaks the
summaries print (round-off shown as 0) and the pose lines. The viewer, the figures,
``feeder simulate`` and the outputs read them back from here."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import numpy as np
import pinocchio as pin

from ..chain.dynamics.elements import force_unit
from ..chain.dynamics.indeterminacy import Indeterminacy
from ..chain.dynamics.inverse import ChainLoads
from ..chain.dynamics.reactions import MountWrench
from ..chain.kinematics.coordinates import coordinates, pose_values
from ..chain.kinematics.frames import PointMotion
from ..chain.kinematics.joints import kind_of
from ..chain.kinematics.tree import reach
from ..chain.model.forces import ForceElement
from ..exceptions import InputError

ROUND_OFF = 1e-9
"""A load's peak at most this share of its scale (:func:`load_scale`) is round-off: the summaries
print it as 0, without a time. The loads are accepted where their equations hold to
:data:`~feeder.chain.dynamics.loads_solve.CONSISTENCY` (1e-9) of their largest term, so nothing
below that share is resolved; a load that is zero in exact arithmetic comes out at ~1e-16 to
1e-13 of the scale (a free joint's reaction, a drive that gravity perpendicular to the motion
does not load)."""


def prismatic(model: pin.Model, joint: str) -> bool:
    """Whether ``joint`` is prismatic (its loads in N, not N·m)."""
    return kind_of(model.joints[model.getJointId(joint)]) == "prismatic"


def load_unit(model: pin.Model, joint: str) -> str:
    """The unit of a one-coordinate joint's generalized force: N (prismatic) or N·m."""
    return "N" if prismatic(model, joint) else "N·m"


def load_columns(loads: ChainLoads) -> dict[str, np.ndarray]:
    """The loads as table columns (N,), SI units, world axes, every joint, closure and element
    named as :func:`column_stem` writes it: ``tau_<joint>`` of the actuated joints (N or N·m
    along the joint axis); ``<closure>_force_x|y|z`` and ``<closure>_moment_x|y|z`` (the cut's
    wrench on the body of its first frame, moment about that frame's origin; the closure's label
    ``frame_a-frame_b`` written ``frame_a_frame_b``); ``<joint>_force_x|y|z`` and
    ``<joint>_moment_x|y|z`` (the wrench the parent exerts on the child, about the joint's
    origin) and their magnitudes ``<joint>_force``, ``<joint>_moment`` (none for a joint that
    transmits no wrench, a free-flyer); ``<element>_force`` of each force element (a spring's or
    cylinder's tension [N], positive pulling its frames together; a joint spring's resistance
    [N·m or N]; the default label ``cylinder:a-b`` written ``cylinder_a_b``); the mount's wrench
    on the mechanism (about the model's origin) ``mount_force_x|y|z``, ``mount_moment_x|y|z`` in
    the level (world) axes and ``mount_force_vehicle_x|y|z``, ``mount_moment_vehicle_x|y|z`` in
    the base's axes, moving with it (the axes of every other column; the same on a base at rest).

    Raises:
        InputError: Two columns of one name (:func:`merge_columns`).
    """
    parts = [{f"tau_{column_stem(name)}": values} for name, values in loads.actuators.items()]
    for label, wrench in loads.closures.items():
        parts.append(_vector_columns(column_stem(label), wrench.force, wrench.moment, False))
    for name, wrench in loads.joints.items():
        parts.append(_vector_columns(column_stem(name), wrench.force, wrench.moment, True))
    parts += [{f"{column_stem(name)}_force": values} for name, values in loads.elements.items()]
    return merge_columns(*parts, mount_columns(loads.mount))


def indeterminate_columns(indeterminacy: Indeterminacy) -> list[str]:
    """The columns of :func:`load_columns` that a rigid model does not determine (their values
    follow the stiffness-weighted convention, :mod:`~feeder.chain.dynamics.indeterminacy`): the
    cuts' and joints' wrench components the self-stresses change, and the magnitudes
    ``<joint>_force``, ``<joint>_moment`` of a joint with such a component; empty when everything
    is determined (the table's sidecar ``indeterminate.txt`` lists them)."""
    names = []
    for entries, magnitudes in ((indeterminacy.closures, False), (indeterminacy.joints, True)):
        for name, components in entries.items():
            stem = column_stem(name)
            for what in ("force", "moment"):
                changed = [c for c in components if c.startswith(what)]
                if changed and magnitudes:
                    names.append(f"{stem}_{what}")
                names += [f"{stem}_{c}" for c in changed]
    return names


def _vector_columns(
    stem: str, force: np.ndarray, moment: np.ndarray, magnitudes: bool
) -> dict[str, np.ndarray]:
    """``<stem>_force_x|y|z`` and ``<stem>_moment_x|y|z`` of a wrench ((N, 3) each), after
    ``<stem>_force`` and ``<stem>_moment``, their magnitudes, if ``magnitudes``."""
    cols: dict[str, np.ndarray] = {}
    for what, vector in (("force", force), ("moment", moment)):
        if magnitudes:
            cols[f"{stem}_{what}"] = np.linalg.norm(vector, axis=1)
        for k, axis in enumerate("xyz"):
            cols[f"{stem}_{what}_{axis}"] = vector[:, k]
    return cols


def merge_columns(*parts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The columns of every part, in order, in one table.

    Raises:
        InputError: Two columns of one name (two joints, closures or force elements whose names
            :func:`column_stem` writes alike, such as ``a-b`` and ``a.b``; or a joint named
            ``mount``), the name given.
    """
    cols: dict[str, np.ndarray] = {}
    for part in parts:
        for key in part:
            if key in cols:
                raise InputError(
                    f"two columns of the table would be named {key!r}: rename one of the "
                    "joints, closures or force elements whose names give it (characters other "
                    "than letters, digits and '_' are written '_')"
                )
        cols |= part
    return cols


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
    return {element.name: force_unit(model, element) for element in elements}


def load_peaks(
    model: pin.Model,
    t: np.ndarray,
    loads: ChainLoads,
    elements: Sequence[ForceElement],
    drives: bool = True,
) -> list[str]:
    """The peak of every drive load (if ``drives``), reaction force, mount wrench and element
    force with its time — or "0 to round-off", without a time, for one that stays within
    :data:`ROUND_OFF` of its scale (:func:`load_scale`) —, the joints that transmit no wrench,
    and the statically indeterminate rows, as summary lines."""
    force_scale = load_scale(model, loads, elements)
    scales = {"N": force_scale, "N·m": force_scale * reach(model, pin.neutral(model)[None])}

    def peak(values: np.ndarray, unit: str) -> str:
        """The largest |value| of ``values`` (N,) [unit], its sign and time; or 0 to round-off."""
        k = int(np.argmax(np.abs(values)))
        if abs(values[k]) <= ROUND_OFF * scales[unit]:
            return f"0 {unit} to round-off (below {ROUND_OFF:g} of {scales[unit]:.4g} {unit})"
        sign = "" if np.all(values >= 0.0) else f" (sign {'+' if values[k] >= 0 else '−'})"
        return f"{abs(values[k]):.4g} {unit}{sign} at t = {t[k]:.4g} s"

    lines = [
        f"  peak actuator load {name}: max |τ| = {peak(values, load_unit(model, name))}"
        for name, values in (loads.actuators.items() if drives else ())
    ]
    for name, wrench in loads.joints.items():
        force = np.linalg.norm(wrench.force, axis=1)
        lines.append(f"  peak reaction force in {name}: {peak(force, 'N')}")
    lines += [
        f"  no reaction in {model.names[j]}: free in all six directions (a free-flyer), it "
        "transmits no force and no moment"
        for j in range(1, model.njoints)
        if model.names[j] not in loads.joints
    ]
    for what, unit, vector in (
        ("force", "N", loads.mount.level_force),
        ("moment", "N·m", loads.mount.level_moment),
    ):
        size = np.linalg.norm(vector, axis=1)
        lines.append(
            f"  peak mount {what} (on the mechanism, about the model's origin): {peak(size, unit)}"
        )
    units = element_units(model, elements)
    for name, values in loads.elements.items():
        lines.append(f"  peak force of {name}: {peak(values, units[name])}")
    return lines + ["  " + line for line in loads.indeterminacy.lines(loads.convention)]


def load_scale(model: pin.Model, loads: ChainLoads, elements: Sequence[ForceElement]) -> float:
    """The loads' scale [N]: the largest force of the run (a joint's, the mount's, a cut's, an
    element's, a prismatic drive's), or its largest moment over the mechanism's size
    (:func:`~feeder.chain.kinematics.tree.reach` at the model's zero pose) if that is larger; a
    moment's scale is this times the size."""
    size = reach(model, pin.neutral(model)[None])
    units = element_units(model, elements) | {
        name: load_unit(model, name) for name in loads.actuators
    }
    scalars = loads.elements | loads.actuators
    wrenches = [(w.force, w.moment) for w in (*loads.joints.values(), *loads.closures.values())]
    wrenches.append((loads.mount.level_force, loads.mount.level_moment))
    forces = [np.abs(x) for name, x in scalars.items() if units[name] == "N"]
    moments = [np.abs(x) for name, x in scalars.items() if units[name] == "N·m"]
    forces += [np.linalg.norm(force, axis=1) for force, _ in wrenches]
    moments += [np.linalg.norm(moment, axis=1) for _, moment in wrenches]
    largest_force = max(float(x.max(initial=0.0)) for x in forces)
    largest_moment = max(float(x.max(initial=0.0)) for x in moments)
    return max(largest_force, largest_moment / size)


def column_stem(name: str) -> str:
    """``name`` (a joint's, a closure's or a force element's) as it appears in the tables'
    column names: each run of characters other than ASCII letters, digits and ``_`` replaced by
    one ``_`` (``cylinder:boom-rod`` → ``cylinder_boom_rod``), so that every column name is one
    that ``numpy.genfromtxt(names=True)``, pandas' attribute access and spreadsheets keep as it
    is."""
    return re.sub(r"[^A-Za-z0-9_]+", "_", name)


def point_columns(motions: Mapping[str, PointMotion]) -> dict[str, np.ndarray]:
    """The mechanism file's points as table columns (N,), world axes (the base's on a moving
    base), each point's name as :func:`column_stem` writes it: ``point_<p>_x|y|z`` its position
    [m], ``point_<p>_velocity_x|y|z`` [m/s] and ``point_<p>_acceleration_x|y|z`` [m/s²]
    (:func:`~feeder.chain.kinematics.frames.point_motion`).

    Raises:
        InputError: Two points whose names :func:`column_stem` writes alike (named).
    """
    parts = []
    for name, motion in motions.items():
        stem = f"point_{column_stem(name)}"
        cols = {}
        for what, vector in (
            ("", motion.position),
            ("_velocity", motion.velocity),
            ("_acceleration", motion.acceleration),
        ):
            for k, axis in enumerate("xyz"):
                cols[f"{stem}{what}_{axis}"] = vector[:, k]
        parts.append(cols)
    return merge_columns(*parts)


def joint_columns(
    model: pin.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> dict[str, np.ndarray]:
    """Every joint's coordinates, rates and accelerations as table columns (N,), SI units, the
    joint's name as :func:`column_stem` writes it:

    * one-coordinate joints (revolute, continuous, prismatic): ``q_<j>``, ``v_<j>``, ``a_<j>``
      (rad or m, and rates; a continuous joint's angle atan2(sin, cos) in (−π, π]);
    * the others: ``q_<j>_<c>`` for each shown coordinate c and ``v_<j>_<r>``, ``a_<j>_<r>`` for
      each velocity component r, named as in :mod:`feeder.chain.kinematics.coordinates`
      (a free-flyer: ``q_<j>_x|y|z``, ``q_<j>_rx|ry|rz``, ``q_<j>_qx|qy|qz|qw``,
      ``v_<j>_vx|vy|vz|wx|wy|wz``).

    Raises:
        InputError: Two joints whose names :func:`column_stem` writes alike (named).
    """
    return merge_columns(*(_joint_columns(model, j, q, v, a) for j in range(1, model.njoints)))


def _key(prefix: str, joint: str, suffix: str) -> str:
    """The column ``<prefix>_<joint>[_<suffix>]`` (:func:`joint_columns`)."""
    return f"{prefix}_{column_stem(joint)}" + (f"_{suffix}" if suffix else "")


def _joint_columns(
    model: pin.Model, j: int, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> dict[str, np.ndarray]:
    """The columns of :func:`joint_columns` for joint ``j``."""
    joint, name, table = model.joints[j], model.names[j], coordinates(model, j)
    shown = table.show(q[:, joint.idx_q : joint.idx_q + joint.nq])
    cols = {_key("q", name, suffix): shown[:, k] for k, (suffix, _) in enumerate(table.shown)}
    for prefix, x in (("v", v), ("a", a)):
        for k, (suffix, _) in enumerate(table.rates):
            cols[_key(prefix, name, suffix)] = x[:, joint.idx_v + k]
    return cols


def q_from_columns(model: pin.Model, cols: Mapping[str, np.ndarray]) -> np.ndarray:
    """The configurations (N, nq) a table's coordinate columns hold: the inverse of
    :func:`joint_columns` (a continuous joint's angle back to its cos, sin; a rotation from its
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
        joint, name, table = model.joints[j], model.names[j], coordinates(model, j)
        shown = np.column_stack([column(_key("q", name, suffix)) for suffix, _ in table.shown])
        q[:, joint.idx_q : joint.idx_q + joint.nq] = table.store(shown)
    return q


def pose_rows(model: pin.Model, q: np.ndarray) -> list[tuple[str, str, float]]:
    """A pose (nq,) as (joint, coordinate, value) rows, SI units: the shown coordinates of
    :mod:`feeder.chain.kinematics.coordinates` (``q`` for a one-coordinate joint's)."""
    return [(name, suffix or "q", value) for name, suffix, value, _ in pose_values(model, q)]


def pose_lines(model: pin.Model, reference: np.ndarray, assembled: np.ndarray) -> list[str]:
    """The assembled pose as text: its distance from the reference and each joint's coordinates
    with their units (:func:`~feeder.chain.kinematics.coordinates.pose_values`)."""
    distance = float(np.linalg.norm(pin.difference(model, reference, assembled)))
    return [
        f"assembled pose (the closed pose nearest to the reference, ‖Δq‖ = {distance:.4g}):",
        *(
            f"  {name} {suffix or 'q'} = {value:.9g}{'' if unit == '–' else ' ' + unit}"
            for name, suffix, value, unit in pose_values(model, assembled)
        ),
    ]
