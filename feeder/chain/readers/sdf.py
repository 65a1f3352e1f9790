"""Strict SDF reading: one ``<model>`` with closed loops → the URDF of a spanning tree + closures.

Pinocchio 4.1's wheel has no SDF support, and URDF cannot hold a loop, so an SDF model is
turned into the URDF text of a spanning tree of its links and the list of
:class:`~feeder.chain.model.closure.Closure` s that close the loops; :func:`load_sdf` builds
the two into a :class:`~feeder.chain.model.closure.ClosedChain`. The steps, each in its module:

* :mod:`~feeder.chain.readers.sdf_model`: what is read from the file (SDF 1.4 to 1.7, one
  model's links, joints and frames) and what is refused;
* :mod:`~feeder.chain.readers.sdf_frames`: SDF's pose frame semantics, placing every link and
  joint frame and every joint axis in the model frame (q = 0 is the SDF's pose);
* :mod:`~feeder.chain.readers.sdf_tree`: the spanning tree from the root link (the base, fixed
  to the world) and the joints it leaves out, which close the loops;
* :mod:`~feeder.chain.readers.sdf_urdf`: the URDF of the tree (joint limits, SDF's inertial
  defaults) and the cut links and closures of the loops.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from pathlib import Path

from lxml import etree

from ...exceptions import InputError
from ..model.closure import ClosedChain, Closure
from .sdf_frames import place
from .sdf_model import SdfModel, parse_model
from .sdf_tree import spanning_tree
from .sdf_urdf import write_cut, write_tree
from .urdf import build_model, check_urdf


def _read_model(path: str | Path, model_name: str | None) -> SdfModel:
    """The model read from the file and placed (every frame in the model frame at q = 0)."""
    model = parse_model(path, model_name)
    place(model)
    return model


def _check_links_argument(model: SdfModel, links: Collection[str] | None) -> set[str]:
    if links is None:
        return set(model.links)
    if isinstance(links, str | bytes) or not isinstance(links, Collection):
        raise InputError(f"links must be a collection of link names, got {links!r}")
    chosen = set(links)
    unknown = sorted(name for name in chosen if name not in model.links)
    if unknown:
        raise InputError(
            f"links {unknown!r} are not in model {model.name!r} ({model.source}); links: "
            f"{sorted(model.links)}"
        )
    return chosen


def _root(model: SdfModel, root_link: str | None, links: set[str]) -> str:
    if root_link is not None:
        if not isinstance(root_link, str) or root_link not in model.links:
            raise InputError(
                f"root link {root_link!r} is not a link of model {model.name!r} "
                f"({model.source}); links: {sorted(model.links)}"
            )
        if root_link not in links:
            raise InputError(f"root link {root_link!r} is not among the links kept")
        return root_link
    children = {j.child for j in model.joints if j.parent in links and j.child in links}
    roots = [name for name in model.links if name in links and name not in children]
    if len(roots) != 1:
        raise InputError(
            f"{model.source}: model {model.name!r} has {len(roots)} links without a parent "
            f"joint ({roots}): give root_link"
        )
    return roots[0]


def read_sdf(
    path: str | Path,
    root_link: str | None = None,
    model_name: str | None = None,
    links: Collection[str] | None = None,
    limits: bool = True,
) -> tuple[str, list[Closure]]:
    """The URDF text of an SDF model's spanning tree and the closures of its loops.

    Args:
        path: The SDF file (meshes are not needed).
        root_link: The link fixed to the world (the URDF's base); default: the one link that
            is no joint's child.
        model_name: Which ``<model>`` to read; default: the only one.
        links: Keep only these links (and the joints between them); default: all.
            :func:`branch_links` selects a branch, e.g. one leg.
        limits: Keep the joints' position limits (default). They must contain the SDF's pose
            (every joint at 0); ``False`` leaves every position limit unset (lower = upper =
            0), for files whose limits do not fit their pose, such as ``cassie_v2.sdf`` (its
            foot joints' limits [−2.4435, −0.6109] rad exclude 0).

    Returns:
        The URDF text (fixed base, every link's inertial, no visuals) and one
        :class:`~feeder.chain.Closure` per cut joint (:mod:`~feeder.chain.readers.sdf_urdf`),
        in file order.

    Raises:
        UrdfError: A missing file, malformed XML, no model, an unsupported element, joint type
            or version, a link not connected to the root, a loop joint that cannot be cut, a
            tree joint whose limits exclude the SDF's pose.
        InputError: Bad arguments: an unknown root link, model or kept link.
        InertiaError: A non-physical inertial.
    """
    model = _read_model(path, model_name)
    kept = _check_links_argument(model, links)
    root = _root(model, root_link, kept)
    edges, cuts = spanning_tree(model, root, kept)
    names = set(model.links) | {j.name for j in model.joints}
    robot, frame = write_tree(model, root, edges, limits)
    closures = [write_cut(robot, joint, frame, names, model) for joint in cuts]
    xml = etree.tostring(robot, pretty_print=True, encoding="unicode")
    check_urdf(xml, f"{model.source} (as URDF)")
    return xml, closures


def load_sdf(
    path: str | Path,
    root_link: str | None = None,
    model_name: str | None = None,
    links: Collection[str] | None = None,
    limits: bool = True,
) -> ClosedChain:
    """The closed chain of an SDF model (:func:`read_sdf`, built with
    :func:`~feeder.chain.readers.urdf.build_model`); its q = 0 is the SDF's pose.

    Raises:
        UrdfError, InputError, InertiaError: See :func:`read_sdf`.
    """
    xml, closures = read_sdf(path, root_link, model_name, links, limits)
    return ClosedChain(build_model(xml, f"{path} (as URDF)"), closures)


def branch_links(
    path: str | Path,
    root_link: str,
    joints: Sequence[str],
    model_name: str | None = None,
) -> frozenset[str]:
    """The root link and every link reached from it through ``joints`` without passing
    through the root again: one branch of the model, e.g. Cassie's left leg is
    ``branch_links(sdf, "pelvis", ["left-roll-op"])``. Pass it as ``links`` to :func:`read_sdf`.

    Args:
        path: The SDF file.
        root_link: The link the branch hangs from.
        joints: Joints of ``root_link`` that start the branch.
        model_name: Which ``<model>``; default: the only one.

    Raises:
        UrdfError: See :func:`read_sdf`.
        InputError: An unknown root link, or a joint that does not touch it.
    """
    model = _read_model(path, model_name)
    if not isinstance(root_link, str) or root_link not in model.links:
        raise InputError(
            f"root link {root_link!r} is not a link of model {model.name!r} ({model.source}); "
            f"links: {sorted(model.links)}"
        )
    if isinstance(joints, str) or not isinstance(joints, Sequence):
        raise InputError(f"joints must be a list of joint names, got {joints!r}")
    by_name = {j.name: j for j in model.joints}
    frontier = []
    for name in joints:
        joint = by_name.get(name)
        if joint is None or root_link not in (joint.parent, joint.child):
            raise InputError(
                f"joint {name!r} is not a joint of link {root_link!r}; its joints: "
                f"{[j.name for j in model.joints if root_link in (j.parent, j.child)]}"
            )
        frontier.append(joint.child if joint.parent == root_link else joint.parent)
    reached = {root_link, *frontier}
    while frontier:
        link = frontier.pop()
        for joint in model.joints:
            if link in (joint.parent, joint.child):
                other = joint.child if joint.parent == link else joint.parent
                if other not in reached:
                    reached.add(other)
                    frontier.append(other)
    return frozenset(reached)
