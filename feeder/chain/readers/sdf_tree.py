"""The spanning tree of an SDF model's links, and the joints it leaves out, which close its loops.

The tree grows from the root link (the base, fixed to the world, whose frame becomes the world
frame: gravity, Pinocchio's −z, is then along the root link's −z, which is the SDF's only when the
root link is upright in the model frame, as Cassie's pelvis is). At each step it takes the first
joint in file order that leads from a link in the tree to one not yet in it, preferring, in this
order, joints a URDF can hold (:data:`TREE_TYPES`) and joints followed from parent to child (as
Pinocchio's SDF parser builds the tree from a link's first parent joint in the file). A joint
followed from child to parent is reversed: its axis changes sign and its coordinate and limits
stay the SDF's. A joint marked ``<physics><simbody><must_be_loop_joint>true`` is never taken.

Every joint left out of the tree closes a loop and is cut
(:func:`~feeder.chain.readers.sdf_urdf.write_cut`): only the types of :data:`CUT_KINDS` can be.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...exceptions import UrdfError
from .sdf_model import SdfJoint, SdfModel

TREE_TYPES = {"revolute", "continuous", "prismatic", "fixed"}
"""SDF joint types a URDF tree can hold."""

CUT_KINDS = {"revolute": "revolute", "continuous": "revolute", "ball": "point", "fixed": "weld"}
"""Closure kind of each SDF joint type that can close a loop."""


@dataclass(frozen=True)
class Edge:
    """A joint of the tree, followed from parent to child or, ``reversed``, from child to
    parent: the URDF joint's parent and child links."""

    joint: SdfJoint
    reversed: bool

    @property
    def urdf_parent(self) -> str:
        return self.joint.child if self.reversed else self.joint.parent

    @property
    def urdf_child(self) -> str:
        return self.joint.parent if self.reversed else self.joint.child


def spanning_tree(
    model: SdfModel, root_link: str, links: set[str]
) -> tuple[list[Edge], list[SdfJoint]]:
    """Tree edges in the order they were taken, and the joints left over (module docstring)."""
    joints = [j for j in model.joints if j.parent in links and j.child in links]
    reached, edges, used = {root_link}, [], set()
    while True:
        best, best_key = None, None
        for joint in joints:
            if joint.name in used or joint.loop_only:
                continue
            if joint.parent in reached and joint.child not in reached:
                reverse = False
            elif joint.child in reached and joint.parent not in reached:
                reverse = True
            else:
                continue
            key = (joint.type not in TREE_TYPES, reverse, joint.index)
            if best_key is None or key < best_key:
                best, best_key = Edge(joint, reverse), key
        if best is None:
            break
        if best.joint.type not in TREE_TYPES:
            raise UrdfError(
                f"{model.source}: link {best.urdf_child!r} is reached from root {root_link!r} "
                f"only through joint {best.joint.name!r} of type {best.joint.type!r}, which a "
                f"URDF tree cannot hold (tree joints: {sorted(TREE_TYPES)})"
            )
        edges.append(best)
        used.add(best.joint.name)
        reached.add(best.urdf_child)
    missing = sorted(links - reached)
    if missing:
        raise UrdfError(
            f"{model.source}: links {missing} are not connected to root {root_link!r} by the "
            "joints kept"
        )
    cuts = [j for j in joints if j.name not in used]
    for joint in cuts:
        if joint.type not in CUT_KINDS:
            raise UrdfError(
                f"{model.source}: joint {joint.name!r} closes a loop but is of type "
                f"{joint.type!r}; only {sorted(CUT_KINDS)} joints can be cut"
            )
    return edges, cuts
