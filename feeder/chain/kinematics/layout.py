"""The shape of a tree that its batched passes reuse on every call: the joints grouped by depth and
kind, their columns, their ancestors' columns — found once per Pinocchio model.

The forward recursion of :mod:`.tree` needs a joint's parent done before it, and nothing more:
every joint of one depth can move at once. A group is the joints of one depth and one kind of
:mod:`.joints` with one coordinate (revolute, continuous, prismatic: the kinds whose relative
motion is one axis, computed for the whole group in one set of array operations); a joint of
another kind is a group of its own. The backward Newton–Euler pass
(:mod:`~feeder.chain.dynamics.newton_euler`) adds each depth's wrenches into their parents',
deepest first. An N-four-bar has depth 2 whatever N: its passes cost a few dozen array
operations, not a few dozen per joint.

The layout is kept per model (:func:`tree_layout`, a weak-keyed cache: it goes with the model)
and found again when the model's size changes (a joint added). It holds only what the joints'
types and the tree's shape decide — never the placements, masses or gravity, which a caller may
change in place and which the passes read at every call.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from .joints import joint_axes, kind_of

SINGLE_AXIS = ("revolute", "continuous", "prismatic")
"""The kinds whose joints move in groups (one coordinate, one axis: :class:`JointGroup`)."""


@dataclass(frozen=True)
class JointGroup:
    """Joints of one depth that move in one set of array operations.

    Attributes:
        kind: Their kind (:func:`~.joints.kind_of`); a kind outside :data:`SINGLE_AXIS` has one
            joint per group.
        joints, parents: Joint ids and their parents' ids, (k,) int.
        iq, iv: Their first coordinate's and velocity's indices, (k,) int.
        axes: Their unit axes in their own frames, (k, 3) (one row per joint of
            :data:`SINGLE_AXIS`; the multi-axis kinds' own (m, 3) for the others).
    """

    kind: str
    joints: np.ndarray
    parents: np.ndarray
    iq: np.ndarray
    iv: np.ndarray
    axes: np.ndarray


@dataclass(frozen=True)
class RowSum:
    """``target[index] += values`` for values (k, ...) whose index (k,) may repeat, the values of
    a repeated index summed (as ``np.add.at``, which is several times slower on these arrays):
    a product with the indices' incidence matrix where an index repeats, found once (:meth:`of`).

    Attributes:
        index: The target rows, (k,) int. unique: The distinct ones, (u,) int.
        incidence: (u, k), 1 where ``index`` is ``unique``; None when no index repeats.
    """

    index: np.ndarray
    unique: np.ndarray
    incidence: np.ndarray | None

    @classmethod
    def of(cls, index: np.ndarray) -> RowSum:
        """The sum into the rows ``index`` (k,) int."""
        if len(set(index.tolist())) == index.size:
            return cls(index, index, None)
        unique, inverse = np.unique(index, return_inverse=True)
        return cls(index, unique, (inverse == np.arange(unique.size)[:, None]).astype(float))

    def add(self, target: np.ndarray, values: np.ndarray) -> None:
        """target[index] += values, in place (target (m, ...), values (k, ...))."""
        if self.incidence is None:
            target[self.index] += values
            return
        summed = self.incidence @ values.reshape(self.index.size, -1)
        target[self.unique] += summed.reshape((self.unique.size, *values.shape[1:]))


@dataclass(frozen=True)
class TreeLayout:
    """A model's tree as its batched passes walk it (module docstring).

    Attributes:
        size: (njoints, nq, nv) of the model it was found for.
        levels: Per depth 1, 2, …, its :class:`JointGroup`\\ s.
        backward: Per depth, deepest first, (children ids (k,) int, the sum into their parents
            :class:`RowSum`): the order in which the backward pass adds wrenches into parents.
        slices: Per joint id, its velocity columns (a slice; empty for the world).
        column_joint: The joint id of each velocity column, (nv,) int.
        support: Per joint id, the velocity columns of the joint and its ancestors, (c,) int.
        ancestors: Per joint id, the joint and its ancestors but the world, (d,) int.
    """

    size: tuple[int, int, int]
    levels: tuple[tuple[JointGroup, ...], ...]
    backward: tuple[tuple[np.ndarray, RowSum], ...]
    slices: tuple[slice, ...]
    column_joint: np.ndarray
    support: tuple[np.ndarray, ...]
    ancestors: tuple[np.ndarray, ...]
    _pairs: dict[tuple[int, int], np.ndarray] = field(
        default_factory=dict, repr=False, compare=False
    )

    def columns(self, a: int, b: int) -> np.ndarray:
        """The velocity columns (sorted, (c,) int) that move joint a's or joint b's body: a
        cut's rows between them are zero in the others (found once per pair)."""
        pair = self._pairs.get((a, b))
        if pair is None:
            pair = self._pairs[(a, b)] = np.union1d(self.support[a], self.support[b])
        return pair


_layouts: weakref.WeakKeyDictionary[pin.Model, TreeLayout] = weakref.WeakKeyDictionary()


def tree_layout(model: pin.Model) -> TreeLayout:
    """The model's :class:`TreeLayout`, found at the first call for this model (or after its size
    changed) and kept with it.

    Raises:
        InputError: A joint type the kinematics do not handle (:func:`~.joints.kind_of`).
    """
    size = (model.njoints, model.nq, model.nv)
    layout = _layouts.get(model)
    if layout is None or layout.size != size:
        layout = _layouts[model] = _find(model)
    return layout


def _find(model: pin.Model) -> TreeLayout:
    count = model.njoints
    parents = list(model.parents)
    depth = [0] * count
    for j in range(1, count):  # parents have smaller ids than their children
        depth[j] = depth[parents[j]] + 1
    axes = joint_axes(model)
    kinds = [""] + [kind_of(model.joints[j]) for j in range(1, count)]
    slices = [slice(0, 0)] + [
        slice(model.joints[j].idx_v, model.joints[j].idx_v + model.joints[j].nv)
        for j in range(1, count)
    ]
    levels, backward = [], []
    for level in range(1, max(depth, default=0) + 1):
        here = [j for j in range(1, count) if depth[j] == level]
        backward.append((np.array(here, int), RowSum.of(np.array([parents[j] for j in here]))))
        groups = []
        for kind in SINGLE_AXIS:
            members = [j for j in here if kinds[j] == kind]
            if members:
                groups.append(_group(model, kind, members, [axes[j][0] for j in members]))
        groups += [
            _group(model, kinds[j], [j], list(axes[j]))
            for j in here
            if kinds[j] not in SINGLE_AXIS
        ]
        levels.append(tuple(groups))
    column_joint = np.zeros(model.nv, int)
    support, ancestors = [np.zeros(0, int)], [np.zeros(0, int)]
    for j in range(1, count):
        column_joint[slices[j]] = j
        own = np.arange(slices[j].start, slices[j].stop)
        support.append(np.concatenate([own, support[parents[j]]]))
        ancestors.append(np.concatenate([[j], ancestors[parents[j]]]).astype(int))
    return TreeLayout(
        (count, model.nq, model.nv),
        tuple(levels),
        tuple(reversed(backward)),
        tuple(slices),
        column_joint,
        tuple(support),
        tuple(ancestors),
    )


def _group(model: pin.Model, kind: str, joints: list[int], axes: list[np.ndarray]) -> JointGroup:
    return JointGroup(
        kind,
        np.array(joints, int),
        np.array([model.parents[j] for j in joints], int),
        np.array([model.joints[j].idx_q for j in joints], int),
        np.array([model.joints[j].idx_v for j in joints], int),
        np.array(axes, dtype=float).reshape(-1, 3),
    )
