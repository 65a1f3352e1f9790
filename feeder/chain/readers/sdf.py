"""Strict SDF reading: one ``<model>`` with closed loops → the URDF of a spanning tree + closures.

Pinocchio 4.1's wheel has no SDF support, and URDF cannot hold a loop, so an SDF model is
turned into the URDF text of a spanning tree of its links and the list of
:class:`~feeder.chain.model.closure.Closure` s that close the loops; :func:`load_sdf` builds
the two into a :class:`~feeder.chain.model.closure.ClosedChain`.

**What is read.** SDF versions 1.4 to 1.7 (``<sdf version>``), one ``<model>`` (directly under
``<sdf>`` or in a ``<world>``): its links (pose and inertial), its joints (type, parent, child,
pose, axis, limits, damping and friction) and, in SDF 1.7, its ``<frame>`` s (only as targets of
``relative_to``). Visuals, collisions, sensors, plugins and the model's own pose are dropped.
Refused with a :class:`~feeder.exceptions.UrdfError` naming the file and the element: nested
models and ``<include>``, a document type declaration (as in :mod:`feeder.chain.readers.urdf`), a
``<pose frame="...">`` naming a frame (SDF 1.5/1.6 left its meaning undefined), ``relative_to``
before SDF 1.7, a number that is not finite, an unknown link or frame, joint types other than
those below.

**Frames** (SDF's "pose frame semantics", units m and rad; rotations as roll-pitch-yaw about
fixed x, y, z, as in URDF). A link's ``<pose>`` is its frame in the model frame, a joint's
``<pose>`` is the joint frame in its *child* link's frame, an ``<inertial>``'s ``<pose>`` is the
centre-of-mass frame in the link's frame (the inertia tensor [kg·m²] is in that frame's axes);
SDF 1.7's ``relative_to`` names another frame (a link, a joint, a ``<frame>`` or
``__model__``). A joint's axis is in the joint frame, except in SDF 1.4 and with
``<use_parent_model_frame>true`` (1.5, 1.6), where it is in the model frame, and in SDF 1.7 with
``<xyz expressed_in="...">``. SDF poses are the assembled configuration with every joint at
zero, so the built model's q = 0 is the SDF's pose and closes every loop.

**The spanning tree.** It grows from the root link (the base, fixed to the world, whose frame
becomes the world frame: gravity, Pinocchio's −z, is then along the root link's −z, which is
the SDF's only when the root link is upright in the model frame, as Cassie's pelvis is). At each
step it takes the first joint in file order that leads from a link in the tree to one not yet
in it, preferring, in this order, joints a URDF can hold (revolute, continuous, prismatic,
fixed) and joints followed from parent to child (as Pinocchio's SDF parser builds the tree from
a link's first parent joint in the file). A joint followed from child to parent is reversed:
its axis changes sign and its coordinate and limits stay the SDF's. A joint marked
``<physics><simbody><must_be_loop_joint>true`` is never taken. Each URDF link frame is the SDF
frame of the joint that reaches it (its SDF link frame when the joint has no pose, as in
Cassie), the root's is its SDF link frame.

**Joints in the URDF.** revolute and prismatic keep their position limits, which must contain
the SDF's pose (0): limits that exclude it belong to another zero than the file's, and are
refused unless the caller drops every position limit (``limits=False``). A continuous joint, a
joint without limits (SDF's default ±1e16 counts as none) or one read with ``limits=False``
becomes a revolute (not Pinocchio's two-coordinate continuous joint) or prismatic joint with
lower = upper = 0, which :mod:`feeder.chain.assembly` reads as "no limit". Effort and velocity
limits that the SDF leaves unset (its default −1) become :data:`UNLIMITED`; damping and friction
are kept; springs (``spring_stiffness``) have no URDF form and are dropped, so a spring joint is
a free joint here (Cassie's shin and heel springs).

**Loops.** Every joint left out of the tree closes a loop and is cut: two massless links,
``<joint>_cut_a`` fixed to the joint's parent link and ``<joint>_cut_b`` fixed to its child
link, both at the joint frame (they coincide at q = 0), and a closure between them: ``revolute``
(about the joint's axis, in both frames' axes) for a revolute or continuous joint, ``point``
for a ball joint, ``weld`` for a fixed joint. Other loop joints are refused.

**Inertials.** SDF's defaults apply: a link without ``<inertial>`` has a mass of 1 kg and an
inertia of 1 kg·m² about each axis (as in Gazebo), a missing ``<mass>`` is 1 kg, a missing
``<ixx>``, ``<iyy>``, ``<izz>`` is 1 kg·m² and a missing product of inertia 0.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin
from lxml import etree

from ...exceptions import InputError, UrdfError
from ..model.closure import ClosedChain, Closure
from .urdf import AXIS_MIN_NORM, build_model, check_urdf, parse_xml_file

SDF_VERSIONS = ("1.4", "1.5", "1.6", "1.7")
"""SDF versions read (their pose and axis conventions are the module docstring's)."""

NO_LIMIT = 1e16
"""Joint position limit [rad or m] at or beyond which an SDF bound means "none": SDF's own
default for ``<lower>``/``<upper>`` is ∓1e16."""

UNLIMITED = float(np.finfo(float).max)
"""Effort [N·m or N] and velocity [rad/s or m/s] limit written for an SDF joint that sets none
(SDF's −1): the largest double, Pinocchio's own default for "no limit" (URDF needs a number)."""

TREE_TYPES = {"revolute", "continuous", "prismatic", "fixed"}
"""SDF joint types a URDF tree can hold."""

CUT_KINDS = {"revolute": "revolute", "continuous": "revolute", "ball": "point", "fixed": "weld"}
"""Closure kind of each SDF joint type that can close a loop."""

SDF_TYPES = {
    "revolute",
    "continuous",
    "prismatic",
    "fixed",
    "ball",
    "revolute2",
    "universal",
    "screw",
    "gearbox",
}
"""Every joint type of SDF 1.4–1.7 (the last four are neither a tree joint nor a cut here)."""

MODEL_FRAME = "__model__"
"""SDF 1.7's name of the model frame."""

# -- reading ---------------------------------------------------------------------------------


@dataclass
class _Link:
    name: str
    pose: etree._Element | None
    inertial: etree._Element | None


@dataclass
class _Joint:
    name: str
    type: str
    parent: str
    child: str
    index: int
    element: etree._Element
    loop_only: bool = False
    placement: pin.SE3 = field(default_factory=pin.SE3.Identity)
    """The joint frame in the model frame at q = 0."""
    axis: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    """Unit axis in the joint frame."""


@dataclass
class _Model:
    source: str
    name: str
    version: str
    links: dict[str, _Link]
    joints: list[_Joint]
    frames: dict[str, etree._Element]
    placements: dict[str, pin.SE3] = field(default_factory=dict)
    """Link frames in the model frame."""


def _read_tree(path: str | Path) -> tuple[etree._Element, str]:
    """Parse the file at ``path`` strictly; returns the ``<sdf>`` element and the file name."""
    if not isinstance(path, str | Path):
        raise InputError(f"path must be a file name, got {path!r}")
    path = Path(path)
    source = str(path)
    root = parse_xml_file(path, "SDF", "sdf")
    version = (root.get("version") or "").strip()
    if version not in SDF_VERSIONS:
        raise UrdfError(
            f"{source}: <sdf version={root.get('version')!r}> is not read here; supported "
            f"versions: {', '.join(SDF_VERSIONS)}"
        )
    return root, source


def _select_model(root: etree._Element, source: str, model_name: str | None) -> etree._Element:
    models = [*root.findall("model"), *root.findall("world/model")]
    names = [m.get("name") for m in models]
    if not models:
        raise UrdfError(f"{source}: no <model> in the file (nor in a <world>)")
    if model_name is None:
        if len(models) > 1:
            raise InputError(f"{source} holds several models {names}: give model_name")
        return models[0]
    if not isinstance(model_name, str):
        raise InputError(f"model_name must be a string, got {model_name!r}")
    chosen = [m for m in models if m.get("name") == model_name]
    if len(chosen) != 1:
        raise InputError(
            f"{source}: no single model named {model_name!r}; models in the file: {names}"
        )
    return chosen[0]


def _parse_model(path: str | Path, model_name: str | None) -> _Model:
    """Read the links, joints and frames of one model and place them (module docstring)."""
    root, source = _read_tree(path)
    version = root.get("version").strip()
    element = _select_model(root, source, model_name)
    name = element.get("name") or "model"
    where = f"{source}: model {name!r}"
    for tag in ("model", "include"):
        if element.find(tag) is not None:
            raise UrdfError(f"{where}: <{tag}> inside a model is not supported; flatten the model")
    links: dict[str, _Link] = {}
    for link in element.findall("link"):
        link_name = link.get("name")
        if not link_name or link_name in links:
            raise UrdfError(f"{where}: every link needs a unique name, got {link_name!r}")
        links[link_name] = _Link(link_name, link.find("pose"), link.find("inertial"))
    if not links:
        raise UrdfError(f"{where}: the model has no <link>")
    joints: list[_Joint] = []
    seen: set[str] = set()
    for index, joint in enumerate(element.findall("joint")):
        joints.append(_parse_joint(joint, index, links, seen, where))
    frames: dict[str, etree._Element] = {}
    if version == "1.7":
        for frame in element.findall("frame"):
            frames[frame.get("name") or ""] = frame
    model = _Model(source, name, version, links, joints, frames)
    _place(model)
    return model


def _parse_joint(
    joint: etree._Element, index: int, links: dict[str, _Link], seen: set[str], where: str
) -> _Joint:
    name, kind = joint.get("name"), joint.get("type")
    if not name or name in seen:
        raise UrdfError(f"{where}: every joint needs a unique name, got {name!r}")
    seen.add(name)
    where = f"{where}, joint {name!r}"
    if kind not in SDF_TYPES:
        raise UrdfError(f"{where}: unknown joint type {kind!r}; SDF types: {sorted(SDF_TYPES)}")
    ends = []
    for tag in ("parent", "child"):
        end = joint.find(tag)
        if end is None or not (end.text or "").strip():
            raise UrdfError(f"{where}: no <{tag}> link")
        ends.append(end.text.strip())
    parent, child = ends
    if "world" in ends:
        raise UrdfError(
            f"{where}: a joint to the world is not supported (the root link is fixed to the "
            "world instead)"
        )
    for end in ends:
        if end not in links:
            raise UrdfError(f"{where}: unknown link {end!r}; links: {sorted(links)}")
    if parent == child:
        raise UrdfError(f"{where}: parent and child are the same link {parent!r}")
    loop_only = _flag(joint.find("physics/simbody/must_be_loop_joint"), f"{where}, simbody")
    return _Joint(name, kind, parent, child, index, joint, loop_only)


def _flag(element: etree._Element | None, where: str) -> bool:
    if element is None:
        return False
    text = (element.text or "").strip().lower()
    if text not in ("true", "1", "false", "0"):
        raise UrdfError(f"{where}: <{element.tag}> must be true or false, got {element.text!r}")
    return text in ("true", "1")


def _numbers(element: etree._Element | None, count: int, where: str, default=None) -> np.ndarray:
    """``count`` finite numbers from an element's text (``default`` when absent or empty)."""
    text = "" if element is None else (element.text or "").strip()
    if not text and default is not None:
        return np.array(default, dtype=float)
    try:
        values = np.array([float(x) for x in text.split()])
    except ValueError:
        values = np.array([])
    if values.size != count or not np.all(np.isfinite(values)):
        tag = "?" if element is None else element.tag
        raise UrdfError(f"{where}: <{tag}> {text!r} is not {count} finite numbers")
    return values


def _pose_value(pose: etree._Element | None, where: str, version: str) -> tuple[pin.SE3, str]:
    """A ``<pose>``'s transform and the frame it is relative to ("" for the default)."""
    if pose is None:
        return pin.SE3.Identity(), ""
    if (pose.get("frame") or "").strip():
        raise UrdfError(
            f"{where}: <pose frame={pose.get('frame')!r}> is not supported (SDF 1.5/1.6 left "
            "its meaning undefined); use SDF 1.7's relative_to"
        )
    relative_to = (pose.get("relative_to") or "").strip()
    if relative_to and version != "1.7":
        raise UrdfError(
            f"{where}: <pose relative_to={relative_to!r}> needs SDF 1.7, the file is {version}"
        )
    v = _numbers(pose, 6, f"{where} pose", default=[0.0] * 6)
    return pin.SE3(pin.rpy.rpyToMatrix(*v[3:]), v[:3]), relative_to


def _place(model: _Model) -> None:
    """Every link's frame and every joint's frame (and axis) in the model frame at q = 0."""
    # Each pose and the frame it is relative to: a name from the file, or the default's key
    # (a joint may share its child link's name before SDF 1.7).
    raw: dict[tuple[str, str], tuple[pin.SE3, str | tuple[str, str]]] = {}
    for link in model.links.values():
        pose, relative_to = _pose_value(
            link.pose, f"{model.source}: link {link.name!r}", model.version
        )
        raw[("link", link.name)] = (pose, relative_to or ("model", ""))
    for joint in model.joints:
        pose, relative_to = _pose_value(
            joint.element.find("pose"), f"{model.source}: joint {joint.name!r}", model.version
        )
        raw[("joint", joint.name)] = (pose, relative_to or ("link", joint.child))
    for name, frame in model.frames.items():
        pose, relative_to = _pose_value(
            frame.find("pose"), f"{model.source}: frame {name!r}", model.version
        )
        attached = (frame.get("attached_to") or "").strip()
        raw[("frame", name)] = (pose, relative_to or attached or ("model", ""))
    placed: dict[tuple[str, str], pin.SE3] = {}

    def key_of(name: str, where: str) -> tuple[str, str]:
        if name == MODEL_FRAME:
            return ("model", "")
        keys = [key for key in (("link", name), ("joint", name), ("frame", name)) if key in raw]
        if len(keys) != 1:
            problem = "is ambiguous (several elements share it)" if keys else "is not a frame"
            raise UrdfError(f"{model.source}: {where}: frame name {name!r} {problem}")
        return keys[0]

    def resolve(key: tuple[str, str], path: tuple[tuple[str, str], ...]) -> pin.SE3:
        if key == ("model", ""):
            return pin.SE3.Identity()
        if key in placed:
            return placed[key]
        if key in path:
            cycle = " → ".join(f"{kind} {name!r}" for kind, name in (*path, key))
            raise UrdfError(f"{model.source}: the poses refer to each other in a cycle: {cycle}")
        pose, relative_to = raw[key]
        if isinstance(relative_to, str):
            relative_to = key_of(relative_to, f"{key[0]} {key[1]!r}")
        base = resolve(relative_to, (*path, key))
        placed[key] = base * pose
        return placed[key]

    for key in raw:
        resolve(key, ())
    model.placements = {name: placed[("link", name)] for name in model.links}
    for joint in model.joints:
        joint.placement = placed[("joint", joint.name)]
        axis = joint.element.find("axis")
        if joint.type in ("fixed", "ball"):
            continue
        where = f"{model.source}: joint {joint.name!r}, axis"
        xyz = None if axis is None else axis.find("xyz")
        vector = _numbers(xyz, 3, where, default=[0.0, 0.0, 1.0])
        norm = float(np.linalg.norm(vector))
        if not norm >= AXIS_MIN_NORM:
            raise UrdfError(f"{where}: {vector.tolist()} is not a direction")
        expressed_in = ""
        if model.version == "1.4":
            expressed_in = MODEL_FRAME
        elif model.version in ("1.5", "1.6"):
            if axis is not None and _flag(axis.find("use_parent_model_frame"), where):
                expressed_in = MODEL_FRAME
        else:
            if axis is not None and axis.find("use_parent_model_frame") is not None:
                raise UrdfError(
                    f"{where}: <use_parent_model_frame> was removed in SDF 1.7; use "
                    '<xyz expressed_in="__model__">'
                )
            if xyz is not None:
                expressed_in = (xyz.get("expressed_in") or "").strip()
        if expressed_in:
            frame = resolve(key_of(expressed_in, f"joint {joint.name!r} axis"), ())
            vector = joint.placement.rotation.T @ frame.rotation @ vector
        joint.axis = vector / norm


# -- the spanning tree and the URDF ----------------------------------------------------------


@dataclass(frozen=True)
class _Edge:
    joint: _Joint
    reversed: bool

    @property
    def urdf_parent(self) -> str:
        return self.joint.child if self.reversed else self.joint.parent

    @property
    def urdf_child(self) -> str:
        return self.joint.parent if self.reversed else self.joint.child


def _spanning_tree(
    model: _Model, root_link: str, links: set[str]
) -> tuple[list[_Edge], list[_Joint]]:
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
                best, best_key = _Edge(joint, reverse), key
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


def _text(values) -> str:
    return " ".join(repr(float(x)) for x in np.ravel(values))


def _origin(parent: etree._Element, placement: pin.SE3) -> None:
    etree.SubElement(
        parent,
        "origin",
        xyz=_text(placement.translation),
        rpy=_text(pin.rpy.matrixToRpy(placement.rotation)),
    )


def _child_number(element: etree._Element | None, tag: str, default: float, where: str) -> float:
    found = None if element is None else element.find(tag)
    if found is None:
        return default
    return float(_numbers(found, 1, where)[0])


def _urdf_inertial(urdf_link: etree._Element, link: _Link, model: _Model, frame: pin.SE3):
    """The link's inertial in its URDF frame ``frame`` (placement in the model frame)."""
    where = f"{model.source}: link {link.name!r}, inertial"
    inertial = link.inertial
    pose = pin.SE3.Identity()
    if inertial is not None:
        pose_element = inertial.find("pose")
        if pose_element is not None and (pose_element.get("relative_to") or "").strip():
            raise UrdfError(f"{where}: relative_to on an inertial pose is not supported")
        pose, _ = _pose_value(pose_element, where, model.version)
    mass = _child_number(inertial, "mass", 1.0, where)
    tensor = None if inertial is None else inertial.find("inertia")
    moments = {
        k: _child_number(tensor, k, 1.0 if k in ("ixx", "iyy", "izz") else 0.0, where)
        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    }
    element = etree.SubElement(urdf_link, "inertial")
    _origin(element, frame.inverse() * model.placements[link.name] * pose)
    etree.SubElement(element, "mass", value=repr(mass))
    etree.SubElement(element, "inertia", {k: repr(v) for k, v in moments.items()})


def _urdf_joint(
    robot: etree._Element, edge: _Edge, model: _Model, origin: pin.SE3, limits: bool
) -> None:
    joint = edge.joint
    where = f"{model.source}: joint {joint.name!r}"
    axis_element = joint.element.find("axis")
    limit = None if axis_element is None else axis_element.find("limit")
    lower = _child_number(limit, "lower", -NO_LIMIT, f"{where}, limit")
    upper = _child_number(limit, "upper", NO_LIMIT, f"{where}, limit")
    limited = (
        limits
        and joint.type in ("revolute", "prismatic")
        and (lower > -NO_LIMIT or upper < NO_LIMIT)
    )
    if limited and not (lower > -NO_LIMIT and upper < NO_LIMIT):
        raise UrdfError(f"{where}: a one-sided limit [{lower:g}, {upper:g}] is not supported")
    if limited and not lower <= 0.0 <= upper:
        raise UrdfError(
            f"{where}: the SDF's pose (joint at 0) is outside the joint's limits "
            f"[{lower:g}, {upper:g}]: the limits do not belong to the pose the file draws, which "
            "is the only one known to close the loops; read with limits=False to drop the "
            "position limits"
        )
    kind = "revolute" if joint.type == "continuous" else joint.type
    element = etree.SubElement(robot, "joint", name=joint.name, type=kind)
    etree.SubElement(element, "parent", link=edge.urdf_parent)
    etree.SubElement(element, "child", link=edge.urdf_child)
    _origin(element, origin)
    if kind == "fixed":
        return
    etree.SubElement(element, "axis", xyz=_text(-joint.axis if edge.reversed else joint.axis))
    rates = {}
    for tag in ("effort", "velocity"):
        value = _child_number(limit, tag, -1.0, f"{where}, limit")
        rates[tag] = repr(value) if value >= 0.0 else repr(UNLIMITED)
    bounds = {"lower": repr(lower), "upper": repr(upper)} if limited else {}
    etree.SubElement(element, "limit", {**bounds, **rates})
    dynamics = None if axis_element is None else axis_element.find("dynamics")
    values = {}
    for tag in ("damping", "friction"):
        value = _child_number(dynamics, tag, 0.0, f"{where}, dynamics")
        if value < 0.0:
            raise UrdfError(f"{where}: <{tag}> {value:g} is negative")
        values[tag] = repr(value)
    etree.SubElement(element, "dynamics", values)


def _check_links_argument(model: _Model, links: Collection[str] | None) -> set[str]:
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


def _root(model: _Model, root_link: str | None, links: set[str]) -> str:
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
        :class:`~feeder.chain.Closure` per cut joint (module docstring), in file order.

    Raises:
        UrdfError: A missing file, malformed XML, no model, an unsupported element, joint type
            or version, a link not connected to the root, a loop joint that cannot be cut, a
            tree joint whose limits exclude the SDF's pose.
        InputError: Bad arguments: an unknown root link, model or kept link.
        InertiaError: A non-physical inertial.
    """
    model = _parse_model(path, model_name)
    kept = _check_links_argument(model, links)
    root = _root(model, root_link, kept)
    edges, cuts = _spanning_tree(model, root, kept)
    names = set(model.links) | {j.name for j in model.joints}
    frame = {root: model.placements[root]}
    robot = etree.Element("robot", name=model.name)
    urdf_links = {root: etree.SubElement(robot, "link", name=root)}
    _urdf_inertial(urdf_links[root], model.links[root], model, frame[root])
    for edge in edges:
        child = edge.urdf_child
        frame[child] = edge.joint.placement
        urdf_links[child] = etree.SubElement(robot, "link", name=child)
        _urdf_inertial(urdf_links[child], model.links[child], model, frame[child])
        origin = frame[edge.urdf_parent].inverse() * frame[child]
        _urdf_joint(robot, edge, model, origin, limits)
    closures = []
    for joint in cuts:
        ends = {}
        for side, link in (("a", joint.parent), ("b", joint.child)):
            name = f"{joint.name}_cut_{side}"
            for generated in (name, f"{name}_fixed"):
                if generated in names:
                    raise UrdfError(
                        f"{model.source}: cutting joint {joint.name!r} needs the name "
                        f"{generated!r}, which the model already uses"
                    )
            names.update((name, f"{name}_fixed"))
            etree.SubElement(robot, "link", name=name)
            element = etree.SubElement(robot, "joint", name=f"{name}_fixed", type="fixed")
            etree.SubElement(element, "parent", link=link)
            etree.SubElement(element, "child", link=name)
            _origin(element, frame[link].inverse() * joint.placement)
            ends[side] = name
        axis = tuple(float(x) for x in joint.axis)
        closures.append(
            Closure(
                ends["a"],
                ends["b"],
                CUT_KINDS[joint.type],
                axis=axis,
                axis_b=axis,
                name=joint.name,
            )
        )
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
    model = _parse_model(path, model_name)
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
