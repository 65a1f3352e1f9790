"""The feeding device's cycle (``feeder view --elevation``) as a
:class:`~feeder.viz.scene.MechanismScene`: the device is a mechanism of one closure (its URDF's
visuals, the rod-eye pin among them), and its extras are given to the one scene builder — the
barrel axis (a :class:`~feeder.viz.overlays.Rod`), the payload's path (a
:class:`~feeder.viz.overlays.Trace`), the paper's loads as arrows (:func:`cycle_forces`) and the
payload waiting on the conveyor until the grip. Device coordinates (y up); on a vehicle (a
:class:`~feeder.chain.BaseMotion`) everything rides on the hull's moving node.

The visuals are the URDF's primitives (frame, cylinder, piston, arm, forearm tray, payload),
animated over the whole cycle. The barrel axis at the elevation ε is a red rod through the
rammed payload, muzzle towards −x; the payload's path, once gripped, a line through its centre
of gravity; MeshCat's x-y-z triad is at the cylinder pivot B. In stage 1 the payload waits on
the conveyor where it is gripped at t = T1.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pinocchio as pin
from lxml import etree

from ..chain import BaseMotion
from ..device.feeder import Feeder
from ..dynamics.cycle import CycleDynamics
from ..exceptions import InputError
from ..motion.cycle import CycleKinematics
from ..validation import check_finite
from .arrows import ARROW_LENGTH, Arrows, ForceSeries
from .legend import LegendEntry, material_css
from .overlays import Rod, Trace
from .placements import joint_placements
from .scene import MechanismScene

STAGES = (
    "the empty forearm swings to the conveyor",
    "the forearm swings back with the payload",
    "the arm lifts the payload to the barrel",
)
"""What happens in each stage of the cycle (REFERENCE.md, section "The feeding cycle")."""

MOUNT_FORCE = "mount force (vehicle on device)"
"""The name (and legend label) of the mount's arrow in :func:`cycle_forces`."""
_BARREL_COLOR, _PATH_COLOR = 0xCC2222, 0xD4A017
_LINK_NUMBERS = {"cylinder": 1, "piston": 2, "arm": 3, "forearm": 4}  # the paper's numbering
_BARREL_RADIUS, _BARREL_BEHIND, _BARREL_AHEAD = 0.006, 0.4, 0.8  # [m] around the rammed CG


def device_scene(
    feeder: Feeder,
    cycle: CycleKinematics,
    forces: Mapping[str, ForceSeries] | None = None,
    *,
    base: BaseMotion | None = None,
) -> MechanismScene:
    """The cycle as a scene, with the arrows of ``forces`` and on the vehicle's moving hull of
    ``base``.

    Args:
        feeder: The device.
        cycle: Its sampled cycle (:func:`~feeder.motion.cycle.feeding_cycle`), N samples.
        forces: Optional arrows by name: forces [N] and application points [m] in the device's
            axes (moving with the hull on a vehicle), each (N, 3) (see
            :data:`~feeder.viz.arrows.ForceSeries`; :func:`cycle_forces` gives the paper's).
        base: The vehicle's motion the device rides on (None: standing level).

    Raises:
        InputError: Bad force names or arrays.
    """
    forces = _check_forces(forces or {}, cycle.t.size)
    model = feeder.model
    title = f"{feeder.params.name} feeder, ε = {np.degrees(cycle.elevation):g}°"
    if base is not None:
        title += f"; {base.describe()}"
    triad = "axes at the cylinder pivot B" if base is None else "level axes at B at rest"
    return MechanismScene(
        model=model,
        visuals=pin.buildGeomFromUrdfString(model, feeder.urdf, pin.GeometryType.VISUAL),
        node="device",
        t=cycle.t,
        joints=joint_placements(model, feeder.to_pinocchio(cycle.q)),
        arrows=Arrows(forces, {}),
        title=title,
        axes=f"{triad}: x red, y green (up), z blue",
        boundaries=tuple(float(b) for b in cycle.spec.boundaries),
        body_legend=_device_legend(feeder),
        overlays=_references(cycle),
        stages=STAGES,
        base=None if base is None else base.state(cycle.t, model.gravity.linear),
        arrow_length=ARROW_LENGTH,
        waiting={"projectile": cycle.gripped == 0},
    )


def _device_legend(feeder: Feeder) -> tuple[LegendEntry, ...]:
    """The URDF's visual materials, once each, in the order of the file."""
    entries: dict[str, LegendEntry] = {}
    for material in etree.fromstring(feeder.urdf.encode("utf-8")).iter("material"):
        color = material.find("color")
        if color is None or material.get("name") in entries:
            continue
        name = material.get("name")
        if name == "projectile":
            label = f"payload ({feeder.params.payload_name})"
        elif name == "pin":
            label = "pins"
        elif name in _LINK_NUMBERS:
            label = f"{name} (link {_LINK_NUMBERS[name]})"
        else:
            label = name
        entries[name] = LegendEntry(material_css(color.get("rgba").split()), "body", label)
    return tuple(entries.values())


def _references(cycle: CycleKinematics) -> tuple[Rod, Trace]:
    """The barrel axis (through the rammed payload's centre of gravity, muzzle towards −x) and
    the payload's path once gripped."""
    direction = np.array([-math.cos(cycle.elevation), math.sin(cycle.elevation), 0.0])
    rammed = cycle.payload_position[-1]
    barrel = Rod(
        "barrel_axis",
        np.array([rammed - _BARREL_BEHIND * direction, rammed + _BARREL_AHEAD * direction]),
        _BARREL_RADIUS,
        _BARREL_COLOR,
        f"barrel axis at ε = {math.degrees(cycle.elevation):g}°",
    )
    path = Trace(
        "payload_path",
        cycle.payload_position[cycle.gripped == 1],
        _PATH_COLOR,
        "payload path (its centre of gravity, once gripped)",
    )
    return barrel, path


def cycle_forces(feeder: Feeder, dynamics: CycleDynamics) -> dict[str, ForceSeries]:
    """The arrows of ``feeder view``: five loads, at five places, in the device's axes (moving
    with the hull on a vehicle).

    * ``piston force``: the cylinder's force on the piston along its axis (Fig. 14), drawn at
      the piston's centre of gravity S (on its line of action);
    * ``arm pivot reaction``: the frame's force on the arm at its pivot A = (L1, L2);
    * ``forearm hinge force``: the arm's force on the forearm at the hinge origin (Fig. 11);
    * ``grip force``: the tray's force on the payload at its centre of gravity (zero before
      the grip);
    * :data:`MOUNT_FORCE`: the force of the vehicle (or of the ground) on the whole device
      through its frame, at the cylinder pivot B (the model's origin): it carries the device's
      weight and inertia.

    The pin force on the arm and the cylinder pivot's reaction are left out: the cylinder and
    piston carry the loop's load along their axis, so both lie on the piston force's line
    with nearly its size, and would hide it.
    """
    p, kinematics = feeder.params, dynamics.kinematics
    q = kinematics.q
    axis = np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0]), np.zeros(len(q))])
    joints = joint_placements(feeder.model, feeder.to_pinocchio(q))
    hinge = joints[:, feeder.model.getJointId("forearm_joint"), :3, 3]
    reactions = dynamics.reactions
    return {
        "piston force": (dynamics.loads.piston_force[:, None] * axis, q[:, 1:2] * axis),
        "arm pivot reaction": (
            reactions.joints["arm_frame"].force,
            np.tile([p.L1, p.L2, 0.0], (len(q), 1)),
        ),
        "forearm hinge force": (reactions.joints["forearm_arm"].force, hinge),
        "grip force": (reactions.grip_force, kinematics.payload_position),
        MOUNT_FORCE: (reactions.mount.force, np.zeros((len(q), 3))),
    }


def _check_forces(forces: Mapping[str, ForceSeries], count: int) -> dict[str, ForceSeries]:
    """``forces`` as float arrays, each named without '/' and of shape (count, 3), else
    InputError."""
    checked = {}
    for name, series in forces.items():
        if not isinstance(name, str) or not name or "/" in name:
            raise InputError(f"force names must be non-empty strings without '/', got {name!r}")
        if len(series) != 2:
            raise InputError(f"force {name!r} must be a pair (force, point), got {series!r}")
        force, point = (check_finite(f"force {name!r}", x) for x in series)
        for what, array in (("forces", force), ("points", point)):
            if array.shape != (count, 3):
                raise InputError(
                    f"force {name!r}: {what} must have shape ({count}, 3) like the cycle, "
                    f"got {array.shape}"
                )
        checked[name] = (force, point)
    return checked
