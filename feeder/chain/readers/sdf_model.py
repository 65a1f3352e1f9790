"""An SDF file read strictly: one ``<model>``'s links, joints and frames, as the file gives them.

**What is read.** SDF versions 1.4 to 1.7 (``<sdf version>``), one ``<model>`` (directly under
``<sdf>`` or in a ``<world>``): its links (pose and inertial), its joints (type, parent, child,
pose, axis, limits, damping and friction) and, in SDF 1.7, its ``<frame>`` s (only as targets of
``relative_to``). Visuals, collisions, sensors, plugins and the model's own pose are dropped.
Refused with a :class:`~feeder.exceptions.UrdfError` naming the file and the element: nested
models and ``<include>``, a document type declaration (as in :mod:`feeder.chain.readers.urdf`),
a number that is not finite, an unknown link, joint types other than :data:`SDF_TYPES`, a joint
to the world (the root link is fixed to it instead).

The poses are placed by :mod:`feeder.chain.readers.sdf_frames`; :mod:`feeder.chain.readers.sdf`
turns the model into a URDF and closures.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin
from lxml import etree

from ...exceptions import InputError, UrdfError
from .urdf import parse_xml_file

SDF_VERSIONS = ("1.4", "1.5", "1.6", "1.7")
"""SDF versions read (their pose and axis conventions:
:mod:`feeder.chain.readers.sdf_frames`)."""

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


@dataclass
class SdfLink:
    """A ``<link>`` as read: its name, and its ``<pose>`` and ``<inertial>`` elements."""

    name: str
    pose: etree._Element | None
    inertial: etree._Element | None


@dataclass
class SdfJoint:
    """A ``<joint>`` as read (its ``index`` in file order); ``placement`` and ``axis`` are set
    when the model is placed (:func:`~feeder.chain.readers.sdf_frames.place`)."""

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
class SdfModel:
    """One ``<model>`` as read from the file ``source`` (SDF ``version``); ``placements`` are
    set when it is placed (:func:`~feeder.chain.readers.sdf_frames.place`)."""

    source: str
    name: str
    version: str
    links: dict[str, SdfLink]
    joints: list[SdfJoint]
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


def parse_model(path: str | Path, model_name: str | None) -> SdfModel:
    """Read the links, joints and frames of one model (module docstring), not yet placed."""
    root, source = _read_tree(path)
    version = root.get("version").strip()
    element = _select_model(root, source, model_name)
    name = element.get("name") or "model"
    where = f"{source}: model {name!r}"
    for tag in ("model", "include"):
        if element.find(tag) is not None:
            raise UrdfError(f"{where}: <{tag}> inside a model is not supported; flatten the model")
    links: dict[str, SdfLink] = {}
    for link in element.findall("link"):
        link_name = link.get("name")
        if not link_name or link_name in links:
            raise UrdfError(f"{where}: every link needs a unique name, got {link_name!r}")
        links[link_name] = SdfLink(link_name, link.find("pose"), link.find("inertial"))
    if not links:
        raise UrdfError(f"{where}: the model has no <link>")
    joints: list[SdfJoint] = []
    seen: set[str] = set()
    for index, joint in enumerate(element.findall("joint")):
        joints.append(_parse_joint(joint, index, links, seen, where))
    frames: dict[str, etree._Element] = {}
    if version == "1.7":
        for frame in element.findall("frame"):
            frames[frame.get("name") or ""] = frame
    return SdfModel(source, name, version, links, joints, frames)


def _parse_joint(
    joint: etree._Element, index: int, links: dict[str, SdfLink], seen: set[str], where: str
) -> SdfJoint:
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
    loop_only = read_flag(joint.find("physics/simbody/must_be_loop_joint"), f"{where}, simbody")
    return SdfJoint(name, kind, parent, child, index, joint, loop_only)


def read_flag(element: etree._Element | None, where: str) -> bool:
    if element is None:
        return False
    text = (element.text or "").strip().lower()
    if text not in ("true", "1", "false", "0"):
        raise UrdfError(f"{where}: <{element.tag}> must be true or false, got {element.text!r}")
    return text in ("true", "1")


def read_numbers(
    element: etree._Element | None, count: int, where: str, default=None
) -> np.ndarray:
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
