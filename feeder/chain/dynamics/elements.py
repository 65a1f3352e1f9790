"""Force elements (:mod:`feeder.chain.model.forces`) on a chain: their generalized forces at one
state (the forward runs' right-hand side), their potential energy, and their body wrenches along
a batched motion (the inverse dynamics and the joint reactions).

Each kind is bound to the chain by a class of its own, registered in :data:`BOUND` under the
input classes it stands for, that owns its formulas (J_f the world-aligned Jacobian of frame f):

=====================  ===================  ===================================================
bound class            input                generalized force Q (nv,); wrenches; energy
=====================  ===================  ===================================================
:class:`LineElement`   Spring, Cylinder     Q = −T gᵀ with ℓ = |p_b − p_a|, u = (p_b − p_a)/ℓ,
                                            g = uᵀ (J_b − J_a) = dℓ/dq, ℓ̇ = g q̇ and the
                                            tension T = k (ℓ − ℓ₀) + c ℓ̇ − P(t) (a cylinder:
                                            k = ℓ₀ = 0, P its push); T u on a's body at p_a,
                                            −T u on b's at p_b; ½ k (ℓ − ℓ₀)²
:class:`JointElement`  JointSpring          Q = −τ on the joint's own coordinate; −τ along the
                                            joint's axis on its child body (a moment for a
                                            revolute joint, a force for a prismatic one), the
                                            opposite on the parent; τ₀ s + ½ k s², s = q − q₀
:class:`LoadElement`   Load                 Q = J_fᵀ w; w on f's body at its origin; none
=====================  ===================  ===================================================

Each wrench is world [force (3) N, moment (3) N·m about the frame's origin], so Q is the virtual
power of an element's wrenches, Σ J_fᵀ w_f, and, for its elastic part, −∂E/∂q. What is not
elastic (dampers, actuator pushes, pressures, loads) is reported as power. A new kind is a frozen
input dataclass in :mod:`~feeder.chain.model.forces` and a :class:`BoundElement` subclass here
with :func:`register`. The module is longer than the others (one concern, the element kinds on a
chain) so that each kind's per-sample and batched formulas sit in one class.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import ClassVar

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError
from ..kinematics.joints import kind_of
from ..kinematics.tree import TreeMotion, cross, frame_placements, frame_velocity
from ..model.closure import ClosedChain
from ..model.forces import Cylinder, ForceElement, JointSpring, Load, Spring, Table, tables_of
from ..model.jacobians import frame_jacobian

WORLD = pin.LOCAL_WORLD_ALIGNED

SHORTEST_LINE = 1e-9
"""[m] A line element shorter than this has no direction: its two frames coincide."""

Wrenches = list[tuple[int, np.ndarray]]
"""Body wrenches along a motion: (frame id, world [force, moment about the frame's origin]
(N, 6))."""


class BoundElement:
    """A force element resolved on a chain (its frames and joint columns found and checked once),
    owning its formulas. The per-sample methods read Pinocchio data the caller has brought to the
    state (:attr:`kinematic`, :attr:`placed`); they are the forward runs' hot path.

    Args:
        chain: The closed chain.
        element: The input (:mod:`~feeder.chain.model.forces`).

    Raises:
        InputError: An unknown frame or joint, named.
    """

    kinematic: ClassVar[bool] = True
    """Whether :meth:`add_generalized` reads the joint Jacobians (``computeJointJacobians`` at
    q)."""
    placed: ClassVar[bool] = False
    """Whether :meth:`energy` reads the frame placements (``updateFramePlacements`` at q)."""

    def __init__(self, chain: ClosedChain, element: ForceElement):
        self.element, self.name, self.model = element, element.name, chain.model
        self.acts = True
        """Whether it has a generalized force (a line between two ground frames has none)."""

    @classmethod
    def unit(cls, model: pin.Model, element: ForceElement) -> str:
        """The unit of the force it reports along a motion (:meth:`wrenches`)."""
        return "N"

    def add_generalized(
        self, data: pin.Data, q: np.ndarray, v: np.ndarray, t: float, out: np.ndarray
    ) -> float:
        """Add its generalized force at (q, v) and time t [s] to ``out`` (nv,); return the power
        [W] of its non-conservative part."""
        raise NotImplementedError

    def energy(self, data: pin.Data, q: np.ndarray) -> float:
        """Its elastic energy [J] at q (none: 0)."""
        return 0.0

    def wrenches(
        self, motion: TreeMotion, q: np.ndarray, v: np.ndarray, t: np.ndarray
    ) -> tuple[Wrenches, np.ndarray | None]:
        """Along a batched motion (N samples at times t [s], (N,)): its body wrenches and the
        force it reports (N,), or None."""
        raise NotImplementedError


BOUND: dict[type, type[BoundElement]] = {}
"""The bound class of each input class."""


def register(*kinds: type) -> Callable[[type[BoundElement]], type[BoundElement]]:
    """Class decorator: bind the input classes ``kinds`` with it. The elements act and report
    in the order their kinds are registered (line elements, joint springs, loads), then in the
    order given."""

    def add(cls: type[BoundElement]) -> type[BoundElement]:
        for kind in kinds:
            BOUND[kind] = cls
        return cls

    return add


def bound_class(element: object) -> type[BoundElement]:
    """The :class:`BoundElement` subclass of ``element``'s kind.

    Raises:
        InputError: ``element`` is not a force element.
    """
    for kind in type(element).__mro__:
        if kind in BOUND:
            return BOUND[kind]
    raise InputError(f"not a force element: {element!r}")


def bind(chain: ClosedChain, element: ForceElement) -> BoundElement:
    """``element`` resolved on ``chain`` by the class of its kind."""
    return bound_class(element)(chain, element)


def force_unit(model: pin.Model, element: ForceElement) -> str:
    """The unit of the force ``element`` reports: N for a line element's tension, N·m or N for
    a joint spring's resistance on a revolute or prismatic joint."""
    return bound_class(element).unit(model, element)


@register(Spring, Cylinder)
class LineElement(BoundElement):
    """A spring or cylinder between the origins of frames a and b: the law
    T = k (ℓ − ℓ₀) + c ℓ̇ − P(t) (module docstring). Its ends on moving bodies are kept with
    their signs in the gap p_b − p_a, the ground's ends as the gap's fixed part."""

    placed: ClassVar[bool] = True

    def __init__(self, chain: ClosedChain, element: Spring | Cylinder):
        super().__init__(chain, element)
        model = chain.model
        self.a, self.b = (chain.frame_id(name) for name in element.frames)
        self.stiffness = element.stiffness
        self.rest_length = element.rest_length
        self.damping = element.damping
        if element.timed:
            self.push = element.push
        else:
            value = element.push(0.0)
            self.push = lambda t: value
        self.moving_ends: list[tuple[int, float]] = []
        self.fixed_gap = np.zeros(3)
        for frame, sign in ((self.b, 1.0), (self.a, -1.0)):
            if model.frames[frame].parentJoint == 0:  # on the ground: oMf is its placement
                self.fixed_gap += sign * model.frames[frame].placement.translation
            else:
                self.moving_ends.append((frame, sign))
        self.acts = bool(self.moving_ends)

    def tension(self, length, rate, push):
        """T [N] at length ℓ [m], rate ℓ̇ [m/s] and push P [N] (floats or arrays alike)."""
        return self.stiffness * (length - self.rest_length) + self.damping * rate - push

    def stretch(self, data: pin.Data, t: float) -> tuple[float, np.ndarray]:
        """Its length ℓ [m] and g = dℓ/dq (nv,) [m/rad or m/m] — the generalized force of a
        unit push, 1 N extending it — on ``data`` brought to q by ``computeJointJacobians``;
        t [s] for the message.

        Raises:
            SingularPoseError: Its two frames coincide (no direction).
        """
        model, ends = self.model, self.moving_ends
        gap = self.fixed_gap
        for frame, sign in ends:  # a sign is ±1: add or subtract, one array operation
            origin = pin.updateFramePlacement(model, data, frame).translation
            gap = gap + origin if sign > 0.0 else gap - origin
        length = math.sqrt(gap.dot(gap))
        if length < SHORTEST_LINE:
            raise SingularPoseError(f"{self.name}: its frames coincide at t = {t:.6g} s")
        row = None  # dℓ/dq = uᵀ (J_b − J_a), (nv,)
        for frame, sign in ends:
            term = (sign / length) * gap.dot(frame_jacobian(model, data, frame, WORLD)[:3])
            row = term if row is None else row + term
        return length, np.zeros(model.nv) if row is None else row  # zero: both ends on ground

    def add_generalized(self, data, q, v, t, out):
        length, row = self.stretch(data, t)
        rate = row.dot(v)
        push = self.push(t)
        out -= self.tension(length, rate, push) * row
        return (push - self.damping * rate) * rate

    def energy(self, data, q):
        gap = data.oMf[self.b].translation - data.oMf[self.a].translation
        return 0.5 * self.stiffness * (math.sqrt(gap @ gap) - self.rest_length) ** 2

    def wrenches(self, motion, q, v, t):
        model, a, b = self.model, self.a, self.b
        _, pa = frame_placements(model, motion, a)
        _, pb = frame_placements(model, motion, b)
        gap = pb - pa
        length = np.linalg.norm(gap, axis=1)
        if np.any(length < SHORTEST_LINE):
            k = int(np.argmax(length < SHORTEST_LINE))
            raise SingularPoseError(f"{self.name}: its two frames coincide at t = {t[k]:g} s")
        direction = gap / length[:, None]
        rate = np.einsum(
            "ni,ni->n",
            direction,
            frame_velocity(model, motion, b, pb) - frame_velocity(model, motion, a, pa),
        )
        push = np.array([self.push(x) for x in t])
        tension = self.tension(length, rate, push)
        pull = tension[:, None] * direction
        zero = np.zeros((t.size, 3))
        return [(a, np.hstack([pull, zero])), (b, np.hstack([-pull, zero]))], tension


@register(JointSpring)
class JointElement(BoundElement):
    """A torsion or linear spring–damper on a revolute or prismatic joint: its resistance
    τ = τ₀ + k (q − q₀) + c q̇ on its own coordinate (module docstring).

    Raises:
        InputError: An unknown joint, or one that is not revolute or prismatic.
    """

    kinematic: ClassVar[bool] = False

    def __init__(self, chain: ClosedChain, element: JointSpring):
        super().__init__(chain, element)
        model = chain.model
        chain.joint_slice(element.joint)  # raises for an unknown joint
        j = model.getJointId(element.joint)
        kind = kind_of(model.joints[j])
        if kind not in ("revolute", "prismatic") or model.joints[j].nq != 1:
            raise InputError(
                f"{element.name}: joint {element.joint!r} must be revolute or prismatic"
            )
        self.joint, self.revolute = j, kind == "revolute"
        self.iq, self.iv = model.joints[j].idx_q, model.joints[j].idx_v
        self.child = _body_frame(model, j, element.name)
        self.parent = _body_frame(model, model.parents[j], element.name)

    @classmethod
    def unit(cls, model, element):
        prismatic = kind_of(model.joints[model.getJointId(element.joint)]) == "prismatic"
        return "N" if prismatic else "N·m"

    def add_generalized(self, data, q, v, t, out):
        element, iv = self.element, self.iv
        out[iv] -= element.resistance(q[self.iq], v[iv])
        return element.power(v[iv])

    def energy(self, data, q):
        return self.element.energy(q[self.iq])

    def wrenches(self, motion, q, v, t):
        model, j = self.model, self.joint
        resistance = self.element.resistance(q[:, self.iq], v[:, self.iv])
        axis = (motion.angular_columns if self.revolute else motion.linear_columns)[:, :, self.iv]
        action = -resistance[:, None] * axis  # on the child: a moment, or a force at o_j
        zero = np.zeros((t.size, 3))
        terms = []
        for frame, sign in ((self.child, 1.0), (self.parent, -1.0)):
            if self.revolute:  # a couple: the same about any point
                terms.append((frame, np.hstack([zero, sign * action])))
            else:
                _, origin = frame_placements(model, motion, frame)
                lever = motion.origin[j] - origin
                terms.append((frame, sign * np.hstack([action, cross(lever, action)])))
        return terms, resistance


@register(Load)
class LoadElement(BoundElement):
    """A force and a moment w on a frame's body at its origin, world axes: Q = J_fᵀ w."""

    def __init__(self, chain: ClosedChain, element: Load):
        super().__init__(chain, element)
        self.frame = chain.frame_id(element.frame)
        self.constant = None if element.timed else element.wrench(0.0)

    def add_generalized(self, data, q, v, t, out):
        wrench = self.element.wrench(t) if self.constant is None else self.constant
        row = wrench.dot(frame_jacobian(self.model, data, self.frame, WORLD))  # J_fᵀ w, (nv,)
        out += row
        return row.dot(v)

    def wrenches(self, motion, q, v, t):
        if self.constant is not None:
            return [(self.frame, np.tile(self.constant, (t.size, 1)))], None
        return [(self.frame, np.array([self.element.wrench(x) for x in t]))], None


class BoundElements:
    """The force elements of a chain, each bound by the class of its kind (:func:`bind`).

    Args:
        chain: The closed chain.
        elements: The force elements.

    Raises:
        InputError: Not a list of force elements, an unknown frame or joint (named), a joint
            spring on a joint that is not revolute or prismatic, two elements of one name.
    """

    def __init__(self, chain: ClosedChain, elements: Sequence[ForceElement] = ()):
        model = chain.model
        self.chain = chain
        self.elements = _element_tuple(elements)
        """The inputs, in the order given."""
        names = [element.name for element in self.elements]
        if len(set(names)) != len(names):
            raise InputError(f"force elements need distinct names, got {names}")
        kinds = list(dict.fromkeys(BOUND.values()))
        self.bound = sorted(
            (bind(chain, element) for element in self.elements),
            key=lambda bound: kinds.index(type(bound)),
        )
        """The bound elements, in the order of their kinds' registration (:func:`register`)."""
        self.tables: list[Table] = tables_of(self.elements)
        self.timed = any(element.timed for element in self.elements)
        """Whether a force varies in time (a table or a function of t)."""
        self.data = model.createData()
        self.model, self.nv = model, model.nv
        acting = [bound for bound in self.bound if bound.acts]
        self.adders = tuple(bound.add_generalized for bound in acting)
        """The generalized forces of the elements that have one (bound once: the hot path)."""
        self.moving = any(bound.kinematic for bound in acting)
        """Whether an acting element needs the joint Jacobians."""
        self.placed = any(bound.placed for bound in self.bound)
        """Whether the energy needs the frame placements."""

    def __bool__(self) -> bool:
        return bool(self.elements)

    def check_covers(self, start: float, end: float) -> None:
        """Raise :class:`InputError` unless every table covers the times [start, end] [s]."""
        for table in self.tables:
            table.check_covers(start, end)

    def generalized(self, q: np.ndarray, v: np.ndarray, t: float) -> tuple[np.ndarray, float]:
        """The elements' generalized force (nv,) and the power [W] of their non-conservative
        parts, at one state (q, v) and time t [s] (trusted).

        The forward runs' right-hand side: one kinematics pass for all elements, and an element's
        end on the ground (a fixed point, no Jacobian) costs nothing."""
        data = self.data
        out = np.zeros(self.nv)
        power = 0.0
        if self.moving:
            pin.computeJointJacobians(self.model, data, q)
        for add in self.adders:
            power += add(data, q, v, t, out)
        return out, power

    def line(self, name: str) -> LineElement | None:
        """The bound line element (a spring or a cylinder) named ``name``, or None if there is
        none of that name or kind."""
        return next((b for b in self.bound if b.name == name and isinstance(b, LineElement)), None)

    def unit_pushes(self, lines: Sequence[LineElement], q: np.ndarray, t: float) -> np.ndarray:
        """The generalized forces (nv, m) of a unit push (1 N, extending) of each of the line
        elements ``lines`` at q, one column each: their g = dℓ/dq (:meth:`LineElement.stretch`;
        a push P adds P g to the forward runs' τ); t [s] for the messages."""
        data = self.data
        pin.computeJointJacobians(self.model, data, q)
        out = np.empty((self.nv, len(lines)))
        for k, line in enumerate(lines):
            out[:, k] = line.stretch(data, t)[1]
        return out

    def energy(self, q: np.ndarray) -> float:
        """Elastic energy [J] stored in the springs and joint springs at q."""
        data = self.data
        if self.placed:
            pin.forwardKinematics(self.model, data, q)
            pin.updateFramePlacements(self.model, data)
        total = 0.0
        for bound in self.bound:
            total += bound.energy(data, q)
        return total

    def wrenches(
        self, motion: TreeMotion, q: np.ndarray, v: np.ndarray, t: np.ndarray
    ) -> tuple[Wrenches, dict[str, np.ndarray]]:
        """Along a batched motion (N samples at times t [s], (N,)): the body wrenches (frame id,
        world [force, moment about the frame's origin] (N, 6)) and each element's force by name
        (N,): a line element's tension [N], a joint spring's resistance [N·m or N]; a load's
        wrench is listed under its frame only."""
        terms, forces = [], {}
        for bound in self.bound:
            wrenches, force = bound.wrenches(motion, q, v, t)
            terms += wrenches
            if force is not None:
                forces[bound.name] = force
        return terms, forces


def _element_tuple(elements: Sequence[ForceElement]) -> tuple[ForceElement, ...]:
    """``elements`` as a tuple, if it is a collection of them (their kinds are checked one by
    one by :func:`bind`)."""
    kinds = ", ".join(kind.__name__ for kind in BOUND)
    if isinstance(elements, tuple(BOUND)):
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
