"""A user's mechanism (``feeder view MODEL``, ``report.html``) as a
:class:`~feeder.viz.scene.MechanismScene`: its bodies (:mod:`feeder.viz.model_visuals`), its
closure cuts and its load arrows, over the motion of a :class:`~feeder.study.view.MechanismView`.

Arrows, from the view's loads table: each actuated joint's drive load at the joint's origin (a
prismatic joint's force along its axis; a revolute joint's moment as a vector along its axis,
right-hand rule, to a scale of its own), the reaction force (parent on child) of the joints
picked, by default the :data:`DEFAULT_REACTIONS` with the largest peak force, and the mount's
force on the mechanism (:data:`MOUNT_FORCE`) at the model's origin. The closure cuts are marked
by balls at each cut's first frame (:class:`~feeder.viz.overlays.CutMarkers`).

On a vehicle (the mechanism file's ``[base]``) the bodies, cuts and arrows ride on the base's
moving node over a flat box, the hull, that shows its motion; every arrow's vector is in the
model's moving axes (the mount's from its ``mount_force_vehicle_x|y|z`` columns).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..chain.kinematics.joints import joint_axes, kind_of
from ..exceptions import InputError
from ..study.mechanism_table import column_stem
from ..study.view import MechanismView
from .arrows import Arrows, ForceSeries
from .legend import note
from .model_visuals import model_bodies
from .overlays import CutMarkers
from .placements import joint_placements
from .scene import MechanismScene

DEFAULT_REACTIONS = 3
"""Joints whose reaction force is drawn when the user picks none: those of largest peak."""

MOUNT_FORCE = "mount force (vehicle or ground on mechanism) [N]"
"""The name (and legend label) of the mount's arrow."""
ROUND_OFF = 1e-9
"""A drive load below this share of the largest reaction force (times the mechanism's size for a
moment) is round-off, not drawn: the loads come from solves whose relative error is ~1e-12 of
the largest load (condition numbers up to ~1e3 on the shipped mechanisms)."""


def model_scene(view: MechanismView, reactions: Sequence[str] | None = None) -> MechanismScene:
    """The mechanism's view as a scene: its bodies, cuts and load arrows over its motion, on its
    vehicle's moving hull if its file has a ``[base]``, with the reaction forces of the joints
    ``reactions`` (default: those of largest peak, :func:`pick_reactions`).

    Raises:
        InputError: A picked reaction that is not in the view's table.

    Warns:
        FeederWarning: Mesh files that are not found or not usable (their visuals are not
            drawn, :func:`~feeder.viz.model_visuals.model_bodies`).
    """
    peaks = reaction_peaks(view)
    picked = pick_reactions(peaks, reactions)
    visuals, legend = model_bodies(view)
    model = view.chain.model
    joints = joint_placements(model, view.q)
    arrows, zero = _arrows(view, joints, peaks, picked)
    title = f"{view.spec.model.name}: {view.source}"
    if view.base is not None:
        title += f"; {view.spec.base.describe()}"
    triad = "axes" if view.base is None else "level axes (the base at rest)"
    return MechanismScene(
        model=model,
        visuals=visuals,
        node="mechanism",
        t=view.t,
        joints=joints,
        arrows=arrows,
        title=title,
        axes=f"{triad} at the model's origin: x red, y green, z blue; {view.note}",
        boundaries=(float(view.t[0]), float(view.t[-1])),
        body_legend=legend,
        overlays=(CutMarkers(view.chain.closures),),
        notes=(note(f"zero drive load (round-off): {', '.join(zero)}"),) if zero else (),
        base=view.base,
    )


def reaction_peaks(view: MechanismView) -> dict[str, float]:
    """Peak reaction force [N] of every joint with a reaction in the view's table."""
    model = view.chain.model
    peaks = {}
    for name in list(model.names)[1:]:
        keys = [f"{column_stem(name)}_force_{axis}" for axis in "xyz"]
        if all(key in view.columns for key in keys):
            force = np.column_stack([view.columns[key] for key in keys])
            peaks[name] = float(np.linalg.norm(force, axis=1).max())
    return peaks


def pick_reactions(peaks: dict[str, float], reactions: Sequence[str] | None) -> list[str]:
    """The joints whose reaction force is drawn: ``reactions`` as given (checked), or the
    :data:`DEFAULT_REACTIONS` of largest peak force, from the peak reaction force [N] of every
    joint with a reaction in the view's table (:func:`reaction_peaks`).

    Raises:
        InputError: A name that is not a joint with a reaction in the table.
    """
    if reactions is None:
        ranked = sorted(peaks, key=peaks.get, reverse=True)
        return [name for name in ranked[:DEFAULT_REACTIONS] if peaks[name] > 0.0]
    unknown = [name for name in reactions if name not in peaks]
    if unknown:
        raise InputError(
            f"no reaction of joint(s) {unknown} to draw; joints: {sorted(peaks) or 'none'}"
        )
    return list(dict.fromkeys(reactions))


def _arrows(
    view: MechanismView, joints: np.ndarray, peaks: dict[str, float], reactions: list[str]
) -> tuple[Arrows, list[str]]:
    """The drive loads, the picked reactions and the mount's force (if the table has it) as
    arrow series (module docstring), model axes, from the joints' placements (N, njoints, 4, 4)
    and the reactions' peaks [N]; and the actuated joints whose drive load is zero (round-off:
    not drawn)."""
    model, columns = view.chain.model, view.columns
    origins, rotations = joints[:, :, :3, 3], joints[:, :, :3, :3]
    axes = joint_axes(model)
    forces: dict[str, ForceSeries] = {}
    moments: dict[str, ForceSeries] = {}
    force_scale = max(peaks.values(), default=0.0)
    lever = float(np.ptp(origins.reshape(-1, 3), axis=0).max())
    zero = []
    for name in list(model.names)[1:]:
        tau = columns.get(f"tau_{column_stem(name)}")
        if tau is None:
            continue
        j = model.getJointId(name)
        prismatic = kind_of(model.joints[j]) == "prismatic"
        if np.abs(tau).max() <= ROUND_OFF * force_scale * (1.0 if prismatic else lever):
            zero.append(name)
            continue
        vector = tau[:, None] * (rotations[:, j] @ axes[j][0])
        if prismatic:
            forces[f"drive force of {name} [N]"] = (vector, origins[:, j])
        else:
            moments[f"drive moment of {name} [N·m]"] = (vector, origins[:, j])
    for name in reactions:
        j = model.getJointId(name)
        force = np.column_stack([columns[f"{column_stem(name)}_force_{axis}"] for axis in "xyz"])
        forces[f"reaction force in {name} [N]"] = (force, origins[:, j])
    mount = [f"mount_force_vehicle_{axis}" for axis in "xyz"]
    if all(key in columns for key in mount):
        force = np.column_stack([columns[key] for key in mount])
        forces[MOUNT_FORCE] = (force, np.zeros_like(force))
    return Arrows(forces, moments), zero
