"""Force elements (:mod:`feeder.chain.model.forces`) on a chain: their generalized forces at one
state (the forward runs' right-hand side) and their body wrenches along a batched motion (the
inverse dynamics and the joint reactions).

A line element (spring, cylinder) between the origins p_a, p_b of frames a, b has length
ℓ = |p_b − p_a|, direction u = (p_b − p_a)/ℓ and rate ℓ̇ = g q̇ with g = uᵀ (J_b − J_a) (J the
frames' world linear Jacobians); its tension T puts T u on a's body at p_a and −T u on b's at
p_b, the generalized force −T gᵀ. A joint spring's resistance τ acts on its joint's child body
(−τ along the joint's axis: a moment for a revolute joint, a force for a prismatic one) and the
opposite on the parent body; its generalized force is −τ on the joint's own coordinate. A load's
wrench w on a frame gives J_fᵀ w (J_f the frame's world-aligned Jacobian).

Energy: springs and joint springs store ½ k s² (+ τ₀ s); dampers, actuator pushes, pressures and
loads do work, reported as the power of the non-conservative forces.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError
from ..kinematics.joints import kind_of
from ..kinematics.tree import TreeMotion, cross, frame_placements
from ..model.closure import ClosedChain
from ..model.forces import (
    Cylinder,
    ForceElement,
    JointSpring,
    Load,
    Spring,
    Table,
    tables_of,
)
from ..model.jacobians import frame_jacobian

WORLD = pin.LOCAL_WORLD_ALIGNED

SHORTEST_LINE = 1e-9
"""[m] A line element shorter than this has no direction: its two frames coincide."""


class BoundElements:
    """Force elements resolved on a chain: frame ids and joint columns checked once.

    Args:
        chain: The closed chain.
        elements: The force elements.

    Raises:
        InputError: An unknown frame or joint (named), a joint spring on a joint that is not
            revolute or prismatic, two elements of one name.
    """

    def __init__(self, chain: ClosedChain, elements: Sequence[ForceElement] = ()):
        model = chain.model
        self.chain = chain
        self.elements = _element_tuple(elements)
        names = [element.name for element in self.elements]
        if len(set(names)) != len(names):
            raise InputError(f"force elements need distinct names, got {names}")
        self.lines: list[_Line] = []
        self.joint_springs: list[tuple[JointSpring, int, int, int, int, bool]] = []
        self.loads: list[tuple[Load, int, np.ndarray | None]] = []
        for element in self.elements:
            if isinstance(element, Spring | Cylinder):
                a, b = (chain.frame_id(name) for name in element.frames)
                self.lines.append(_Line(model, element, a, b))
            elif isinstance(element, JointSpring):
                chain.joint_slice(element.joint)  # raises for an unknown joint
                j = model.getJointId(element.joint)
                kind = kind_of(model.joints[j])
                if kind not in ("revolute", "prismatic") or model.joints[j].nq != 1:
                    raise InputError(
                        f"{element.name}: joint {element.joint!r} must be revolute or prismatic"
                    )
                self.joint_springs.append(
                    (
                        element,
                        model.joints[j].idx_q,
                        model.joints[j].idx_v,
                        _body_frame(model, j, element.name),
                        _body_frame(model, model.parents[j], element.name),
                        kind == "revolute",
                    )
                )
            elif isinstance(element, Load):
                constant = None if element.table is not None else element.wrench(0.0)
                self.loads.append((element, chain.frame_id(element.frame), constant))
            else:
                raise InputError(f"not a force element: {element!r}")
        self.tables: list[Table] = tables_of(self.elements)
        self.timed = bool(self.tables) or any(
            callable(getattr(element, key, None))
            for element in self.elements
            for key in ("force", "pressure", "rod_pressure")
        )
        """Whether a force varies in time (a table or a function of t)."""
        self.data = model.createData()
        self.model, self.nv = model, model.nv
        self.moving_lines = [line for line in self.lines if line.moving_ends]
        """The line elements with an end on a moving body (one between two ground frames
        gives no generalized force and does no work)."""
        self.moving = bool(self.loads) or bool(self.moving_lines)
        """Whether an element needs the kinematics (a line with an end on a moving body, a
        load)."""

    def __bool__(self) -> bool:
        return bool(self.elements)

    def check_covers(self, start: float, end: float) -> None:
        """Raise :class:`InputError` unless every table covers the times [start, end] [s]."""
        for table in self.tables:
            table.check_covers(start, end)

    # -- one state ---------------------------------------------------------------------------

    def generalized(self, q: np.ndarray, v: np.ndarray, t: float) -> tuple[np.ndarray, float]:
        """The elements' generalized force (nv,) and the power [W] of their non-conservative
        parts, at one state (q, v) and time t [s] (trusted).

        The forward runs' right-hand side: one kinematics pass for all elements, and an element's
        end on the ground (a fixed point, no Jacobian) costs nothing."""
        model, data = self.model, self.data
        out = np.zeros(self.nv)
        power = 0.0
        if self.moving:
            pin.computeJointJacobians(model, data, q)
        for line in self.moving_lines:
            gap = line.fixed_gap
            for frame, sign in line.moving_ends:
                gap = gap + sign * pin.updateFramePlacement(model, data, frame).translation
            length = math.sqrt(gap.dot(gap))
            if length < SHORTEST_LINE:
                raise SingularPoseError(
                    f"{line.element.name}: its frames coincide at t = {t:.6g} s"
                )
            row = 0.0  # dℓ/dq = uᵀ (J_b − J_a), (nv,)
            for frame, sign in line.moving_ends:
                linear = frame_jacobian(model, data, frame, WORLD)[:3]
                row = row + (sign / length) * gap.dot(linear)
            rate = row.dot(v)
            push = line.push(t)
            out -= line.tension(length, rate, push) * row
            power += (push - line.damping * rate) * rate
        for element, iq, iv, *_ in self.joint_springs:
            out[iv] -= element.resistance(q[iq], v[iv])
            power += element.power(v[iv])
        for element, f, constant in self.loads:
            wrench = element.wrench(t) if constant is None else constant
            row = wrench.dot(frame_jacobian(model, data, f, WORLD))  # J_fᵀ w, (nv,)
            out += row
            power += row.dot(v)
        return out, power

    def energy(self, q: np.ndarray) -> float:
        """Elastic energy [J] stored in the springs and joint springs at q."""
        model, data = self.model, self.data
        total = 0.0
        if self.lines:
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacements(model, data)
        for line in self.lines:
            gap = data.oMf[line.b].translation - data.oMf[line.a].translation
            total += 0.5 * line.stiffness * (math.sqrt(gap @ gap) - line.rest_length) ** 2
        for element, iq, *_ in self.joint_springs:
            total += element.energy(q[iq])
        return total

    # -- along a motion ----------------------------------------------------------------------

    def wrenches(
        self, motion: TreeMotion, q: np.ndarray, v: np.ndarray, t: np.ndarray
    ) -> tuple[list[tuple[int, np.ndarray]], dict[str, np.ndarray]]:
        """Along a batched motion (N samples at times t [s], (N,)): the body wrenches (frame id,
        world [force, moment about the frame's origin] (N, 6)) and each element's force by name
        (N,): a line element's tension [N], a joint spring's resistance [N·m or N]; a load's
        wrench is listed under its frame only."""
        model = self.chain.model
        n = t.size
        terms, forces = [], {}
        for line in self.lines:
            element, a, b = line.element, line.a, line.b
            _, pa = frame_placements(model, motion, a)
            _, pb = frame_placements(model, motion, b)
            gap = pb - pa
            length = np.linalg.norm(gap, axis=1)
            if np.any(length < SHORTEST_LINE):
                k = int(np.argmax(length < SHORTEST_LINE))
                raise SingularPoseError(
                    f"{element.name}: its two frames coincide at t = {t[k]:g} s"
                )
            direction = gap / length[:, None]
            rate = np.einsum(
                "ni,ni->n",
                direction,
                _velocity(model, motion, b, pb) - _velocity(model, motion, a, pa),
            )
            push = np.array([line.push(x) for x in t])
            tension = line.tension(length, rate, push)
            pull = tension[:, None] * direction
            terms.append((a, np.hstack([pull, np.zeros((n, 3))])))
            terms.append((b, np.hstack([-pull, np.zeros((n, 3))])))
            forces[element.name] = tension
        for element, iq, iv, child, parent, revolute in self.joint_springs:
            j = model.frames[child].parentJoint
            resistance = element.resistance(q[:, iq], v[:, iv])
            axis = (motion.angular[j] if revolute else motion.linear[j])[:, :, 0]
            action = -resistance[:, None] * axis  # on the child: a moment, or a force at o_j
            zero = np.zeros((n, 3))
            for frame, sign in ((child, 1.0), (parent, -1.0)):
                if revolute:  # a couple: the same about any point
                    terms.append((frame, np.hstack([zero, sign * action])))
                else:
                    _, origin = frame_placements(model, motion, frame)
                    lever = motion.origin[j] - origin
                    terms.append((frame, sign * np.hstack([action, cross(lever, action)])))
            forces[element.name] = resistance
        for element, f, constant in self.loads:
            wrench = np.tile(constant, (n, 1)) if constant is not None else None
            terms.append(
                (f, wrench if wrench is not None else np.array([element.wrench(x) for x in t]))
            )
        return terms, forces


class _Line:
    """A line element's law T = k (ℓ − ℓ₀) + c ℓ̇ − P(t) (a cylinder: k = 0, P its push), and its
    two ends: the frames on moving bodies with their signs in ℓ's gap p_b − p_a, the ground's
    fixed part of the gap."""

    def __init__(self, model: pin.Model, element: Spring | Cylinder, a: int, b: int):
        self.element, self.a, self.b = element, a, b
        spring = isinstance(element, Spring)
        self.stiffness = element.stiffness if spring else 0.0
        self.rest_length = element.rest_length if spring else 0.0
        self.damping = element.damping
        constant = not spring or not callable(element.force)
        if spring and constant:
            value = float(element.force)
            self.push = lambda t: value
        else:
            self.push = element.push
        self.moving_ends: list[tuple[int, float]] = []
        self.fixed_gap = np.zeros(3)
        for frame, sign in ((b, 1.0), (a, -1.0)):
            if model.frames[frame].parentJoint == 0:  # on the ground: oMf is its placement
                self.fixed_gap += sign * model.frames[frame].placement.translation
            else:
                self.moving_ends.append((frame, sign))

    def tension(self, length, rate, push):
        """T [N] at length ℓ [m], rate ℓ̇ [m/s] and push P [N] (floats or arrays alike)."""
        return self.stiffness * (length - self.rest_length) + self.damping * rate - push


def _element_tuple(elements: Sequence[ForceElement]) -> tuple[ForceElement, ...]:
    """``elements`` as a tuple, if it is a collection of them (their kinds are checked one by
    one by :class:`BoundElements`)."""
    kinds = "Spring, Cylinder, JointSpring, Load"
    if isinstance(elements, ForceElement):
        raise InputError(
            f"elements must be a list of force elements, got the single element "
            f"{elements.name!r}: put it in a list, [element]"
        )
    if isinstance(elements, str | bytes | Mapping) or not isinstance(elements, Iterable):
        raise InputError(f"elements must be a list of force elements ({kinds}), got {elements!r}")
    return tuple(elements)


def _body_frame(model: pin.Model, joint: int, name: str) -> int:
    """A frame on the body of joint ``joint`` (the world's for 0): where a joint spring's two
    wrenches are applied."""
    for f in range(len(model.frames)):
        if model.frames[f].parentJoint == joint:
            return f
    raise InputError(f"{name}: the body of joint {model.names[joint]!r} has no frame")


def _velocity(model: pin.Model, motion: TreeMotion, frame: int, point: np.ndarray) -> np.ndarray:
    """World velocity (N, 3) of a frame's origin at ``point`` (N, 3)."""
    j = model.frames[frame].parentJoint
    return motion.velocity[j] + cross(motion.omega[j], point - motion.origin[j])
