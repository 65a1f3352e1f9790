"""Joint reactions: Newton and Euler for the whole mechanism, joint axes, the grip."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from feeder.chain.kinematics.tree import tree_motion
from feeder.device.parameters import GRAVITY

BALANCE_TOLERANCE = 1e-10
"""Relative to the peak reaction: Newton–Euler of the whole mechanism from two Pinocchio
algorithms (RNEA joint forces vs centre-of-mass / centroidal-momentum rates); each is exact up
to rounding (~1e-13 of the loads)."""

DRIVE_TOLERANCE = 1e-10
"""Relative to the peak piston force × 1 m: the passive pivots' moments about their axes are
zero up to the rounding of the 3 × 3 solves (~1e-13)."""

GRIP_TOLERANCE = 1e-10
"""Relative to the payload's weight: the grip wrench from the payload's spatial inertia vs the
difference of two RNEA runs (with and without payload), both exact up to rounding."""

LEVER = 1.0
"""[m] Scale of the lever arms (the device is ~1 m): turns a force tolerance into a moment one."""

VELOCITY_ROUNDING = 1e-13
"""Relative to the largest payload speed: rounding of a difference of two velocities (eps =
2.2e-16), with a margin of ~500 for Pinocchio's composition of the frame velocity."""


def _peak(result) -> float:
    return max(
        np.linalg.norm(wrench.force, axis=1).max() for wrench in result.reactions.joints.values()
    )


def test_newton_euler_of_the_whole_mechanism(result, dyn):
    """Frame reactions (cylinder–frame + arm–frame) + gravity = Σ mᵢ a_Gᵢ, and their moments
    about the world origin = rate of the angular momentum about it."""
    kin, joints = result.kinematics, result.reactions.joints
    frame_joints = (joints["cylinder_frame"], joints["arm_frame"])
    origins = (dyn.joint_ids[0], dyn.joint_ids[2])
    force_scale = BALANCE_TOLERANCE * _peak(result)
    for k in range(kin.t.size):
        case = dyn.cases[kin.gripped[k]]
        model, data = case.model, case.data
        q, v, a = (dyn.to_pinocchio(x[k]) for x in (kin.q, kin.v, kin.a))
        rate = pin.computeCentroidalMomentumTimeVariation(model, data, q, v, a)
        pin.centerOfMass(model, data, q, v, a)
        mass, com = data.mass[0], data.com[0]
        external = sum(j.force[k] for j in frame_joints) + mass * GRAVITY
        assert np.abs(external - mass * data.acom[0]).max() <= force_scale
        assert np.abs(rate.linear - mass * data.acom[0]).max() <= force_scale
        moment = mass * np.cross(com, GRAVITY)
        for wrench, joint in zip(frame_joints, origins, strict=True):
            moment += wrench.moment[k] + np.cross(data.oMi[joint].translation, wrench.force[k])
        angular_rate = rate.angular + np.cross(com, rate.linear)
        assert np.abs(moment - angular_rate).max() <= force_scale * LEVER


def test_joint_axes_carry_the_drives_only(result):
    """About its axis a passive pivot carries nothing, an actuated joint its actuator load."""
    joints, loads = result.reactions.joints, result.loads
    scale = DRIVE_TOLERANCE * np.abs(loads.piston_force).max()
    assert np.abs(joints["cylinder_frame"].drive).max() <= scale
    assert np.abs(joints["arm_frame"].drive).max() <= scale
    assert np.abs(joints["piston_cylinder"].drive - loads.piston_force).max() <= scale
    assert np.abs(joints["forearm_arm"].drive - loads.forearm_torque).max() <= scale


def test_piston_side_force_is_perpendicular_to_the_axis(result):
    q = result.kinematics.q
    axis = np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0]), np.zeros(len(q))])
    piston = result.reactions.joints["piston_cylinder"]
    scale = DRIVE_TOLERANCE * np.abs(result.loads.piston_force).max()
    assert np.abs(np.sum(piston.constraint_force * axis, axis=1)).max() <= scale
    along = np.sum(piston.force * axis, axis=1)
    assert np.abs(along - result.loads.piston_force).max() <= scale


def test_out_of_plane_load_goes_to_the_arm_pivot(result):
    """The minimum-norm pin force (z = 0): the cylinder carries no out-of-plane load, the arm
    pivot all of it (the forearm swings in the horizontal plane in stages 1–2)."""
    joints = result.reactions.joints
    scale = BALANCE_TOLERANCE * _peak(result)
    assert np.abs(result.reactions.closure_force[:, 2]).max() == 0.0
    assert np.abs(joints["cylinder_frame"].force[:, 2]).max() <= scale
    assert np.abs(joints["cylinder_frame"].constraint_moment).max() <= scale
    assert np.abs(joints["arm_frame"].constraint_moment).max() > 1.0  # [N·m]: it is real


def test_grip_is_the_payload_share_of_the_forearm_joint_wrench(result, dyn):
    """Grip (about the payload CG, world) transported to the forearm joint = RNEA's forearm
    joint wrench with the payload minus without it."""
    kin, grip = result.kinematics, result.reactions
    forearm = dyn.joint_ids[3]
    rotations = tree_motion(dyn.cases[1].model, dyn.to_pinocchio(kin.q)).rotation[forearm]
    lever = dyn.payload_inertia.lever
    scale = GRIP_TOLERANCE * dyn.payload_inertia.mass * np.linalg.norm(GRAVITY)
    gripped = np.flatnonzero(kin.gripped)
    assert np.all(grip.grip_force[kin.gripped == 0] == 0.0)
    for k in gripped[::3]:
        q, v, a = (dyn.to_pinocchio(x[k]) for x in (kin.q, kin.v, kin.a))
        wrenches = []
        for case in dyn.cases[::-1]:
            pin.rnea(case.model, case.data, q, v, a)
            wrenches.append(case.data.f[forearm].vector.copy())
        difference = wrenches[0] - wrenches[1]
        force = rotations[k].T @ grip.grip_force[k]
        moment = rotations[k].T @ grip.grip_moment[k] + np.cross(lever, force)
        assert np.abs(force - difference[:3]).max() <= scale
        assert np.abs(moment - difference[3:]).max() <= scale * LEVER


def test_grip_force_is_mass_times_acceleration_minus_gravity(result, dyn):
    """m (a_G − g) with a_G by central differences of the payload's velocity (Fig. 8)."""
    kin = result.kinematics
    h = kin.t[1] - kin.t[0]
    velocity = kin.payload_velocity
    acceleration = (velocity[2:] - velocity[:-2]) / (2 * h)
    inside = np.ones(kin.t.size - 2, dtype=bool)
    for start in np.flatnonzero(np.diff(kin.stage)) + 1:  # the jerk jumps at stage starts
        inside[max(start - 3, 0) : start + 2] = False
    inside &= kin.gripped[1:-1] == 1
    mass = dyn.payload_inertia.mass
    expected = mass * (acceleration - GRAVITY)
    # Central difference error ≤ h²/6 · max|v'''|, v''' from third differences; + rounding.
    third = np.abs(np.diff(velocity, 3, axis=0)).max() / h**3
    tolerance = mass * (h**2 / 6.0 * third + VELOCITY_ROUNDING * np.abs(velocity).max() / h)
    error = np.abs(result.reactions.grip_force[1:-1][inside] - expected[inside]).max()
    assert error <= tolerance
